//! Debugging aid: run the plain kinetic structure of a scenario up to a time
//! and print the corridors, certificates and partition triangles that involve
//! two bodies.
//!
//! `cargo run -p kss-cli --example structure_dump -- SCENARIO.json TIME BODY BODY`

use kss::num::{Rational, Time};
use kss::structure::geo::Geo;
use kss::structure::kinetic::{Kinetic, Step};
use kss::structure::Obj;
use kss::world::{BodyId, World};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let s: kss::Scenario =
        kss::json::parse_scenario(&std::fs::read_to_string(&a[1]).unwrap()).unwrap();
    let until: f64 = a[2].parse().unwrap();
    let x: u32 = a[3].parse().unwrap();
    let y: u32 = a[4].parse().unwrap();
    let world = World::new(&s, None).unwrap();
    let world = Geo::plain(&world);
    let mut k = Kinetic::new(&world, &Rational::zero()).unwrap();
    let lim = Time::from_f64(until).unwrap();
    loop {
        match k.step(&world, &lim, &[], &|_, _, _| true).unwrap() {
            Step::Idle => break,
            st => eprintln!("{st:?}"),
        }
    }
    let has = |o: Obj| o == Obj::Body(BodyId::new(x)) || o == Obj::Body(BodyId::new(y));
    for (i, c) in k.kss.corrs.iter().enumerate() {
        if has(c.a) && has(c.b) {
            println!(
                "corr {i}: {c:?} ends {:?}",
                k.kss.ends(kss::structure::CorrId(i as u32))
            );
            println!(
                "   certs {:?}",
                k.kss
                    .corridor_certs(&world, kss::structure::CorrId(i as u32), &lim)
            );
        }
    }
    for (i, t) in k.kss.tris.iter().enumerate() {
        if t.c.iter().any(|c| has(c.obj)) {
            println!("tri {i}: {:?}", t.c);
        }
    }
}
