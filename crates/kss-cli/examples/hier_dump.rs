//! Debugging aid: run a scenario with the kinetic structure (hierarchical
//! unless `plain` is given) up to a time and print every certificate with
//! its owners and failure time, and each body's exposed approximation (the
//! hierarchy approximates every polygon here).
//!
//! `cargo run -p kss-cli --example hier_dump -- SCENARIO.json TIME [plain]`

use kss::{RunOptions, StructureKind};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let s: kss::Scenario =
        kss::json::parse_scenario(&std::fs::read_to_string(&a[1]).unwrap()).unwrap();
    let time: f64 = a[2].parse().unwrap();
    let structure = if a.get(3).map(String::as_str) == Some("plain") {
        StructureKind::Plain
    } else {
        StructureKind::Hierarchical
    };
    let options = RunOptions {
        structure,
        audit: true,
        approximate_above: 0,
        ..Default::default()
    };
    let state = kss::runner::plain_state_at(&s, &options, time).unwrap();
    let geo = kss::structure::geo::Geo {
        world: &state.world,
        shapes: &state.shapes,
    };
    for (c, owners, t) in state.kinetic.certificate_list(&geo) {
        println!(
            "{:?} {:?} {:?} owners {:?} fails {:?}",
            c.kind,
            c.p.map(|p| (p.obj, p.v)),
            c.sign,
            owners,
            t.map(|t| t.to_f64())
        );
    }
    for (i, c) in state.kinetic.kss.corrs.iter().enumerate() {
        println!("corridor {i}: {c:?}");
    }

    for k in 0..state.kinetic.kss.corrs.len() {
        let faces = state
            .kinetic
            .kss
            .corridor_faces(&geo, kss::structure::CorrId(k as u32));
        for f in faces {
            let f: Vec<String> = f.iter().map(|a| format!("{:?}.{}", a.obj, a.v)).collect();
            println!("corridor {k} face: {}", f.join(" "));
        }
    }
    for b in 0..state.world.len() {
        let id = kss::world::BodyId::new(b as u32);
        if !state.world.body(id).alive {
            continue;
        }
        let seen: Vec<String> = geo
            .ids(id)
            .into_iter()
            .map(|v| {
                let a = kss::structure::Att::vertex(id, v);
                let p = geo.position(a, &state.time).expect("finite").to_f64();
                let real = if geo.is_real(a) { "" } else { "*" };
                format!("{v}{real} ({:.4}, {:.4})", p[0], p[1])
            })
            .collect();
        println!(
            "body {b} ({}): {}",
            state.world.body(id).id,
            seen.join(", ")
        );
    }
}
