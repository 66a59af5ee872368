//! [`flypast`]: two congruent regular n-gons passing each other at a chosen
//! minimum distance, placed with exact dyadic arithmetic ([`Dy`]).
//!
//! `Dy` keeps its own conversion to a double ([`Dy::to_f64`]): the placement
//! and the reported gap ([`FlypastInfo::achieved_gap`]) round through it, and
//! it gives infinity once the unreduced mantissa has more than 1024 bits
//! (a gap hundreds of orders of magnitude beyond the diameter, such as
//! diameter 1e-300 and gap 1e99), where `crate::num::Rational::to_f64` gives
//! a finite number.

use super::InvalidParams;
use std::f64::consts::{PI, TAU};

use dashu_int::IBig;

use super::check_or_panic;
use crate::rng::Rng;
use crate::scenario::{CollisionMode, PolygonSpec, Scenario};

/// Parameters of [`flypast`].
#[derive(Clone, Debug, PartialEq)]
pub struct FlypastParams {
    /// Vertices of each polygon (3 to 2^24).
    pub n: usize,
    /// Diameter of the circumscribed circle of each polygon.
    pub diameter: f64,
    /// The minimum distance between the polygons during the motion; zero or
    /// negative: they collide (a negative gap is a penetration depth of the
    /// relative path into the Minkowski difference, at least `-diameter / 2`).
    pub gap: f64,
    /// Whether A moves too (A and B then move in opposite directions at half
    /// the speed each); otherwise A is fixed.
    pub a_moving: bool,
    /// The speed of B relative to A.
    pub speed: f64,
    /// Collision mode of the scenario.
    pub mode: CollisionMode,
    /// Seed of the rotations and the direction of motion.
    pub seed: u64,
}

impl Default for FlypastParams {
    fn default() -> Self {
        FlypastParams {
            n: 64,
            diameter: 1.0,
            gap: 0.1,
            a_moving: false,
            speed: 1.0,
            mode: CollisionMode::Stop,
            seed: 0,
        }
    }
}

impl FlypastParams {
    /// Checks the parameters; the error says which one is wrong.
    pub fn check(&self) -> Result<(), InvalidParams> {
        if self.n < 3 || self.n > 1 << 24 {
            return Err(InvalidParams(format!(
                "n is {}: it must be between 3 and 2^24",
                self.n
            )));
        }
        if !(self.diameter.is_finite() && self.diameter > 0.0 && self.diameter < 1e100) {
            return Err(InvalidParams(format!(
                "diameter is {}: it must be a finite number > 0",
                self.diameter
            )));
        }
        if !(self.gap.is_finite() && self.gap >= -self.diameter / 2.0 && self.gap < 1e100) {
            return Err(InvalidParams(format!(
                "gap is {}: it must be finite and at least -diameter/2 = {}",
                self.gap,
                -self.diameter / 2.0
            )));
        }
        if !(self.speed.is_finite() && self.speed > 0.0 && self.speed < 1e100) {
            return Err(InvalidParams(format!(
                "speed is {}: it must be a finite number > 0",
                self.speed
            )));
        }
        // the construction squares the speed and divides the sizes by it
        let span = 3.0 * (self.diameter + self.gap.abs()) / self.speed;
        if !(self.speed * self.speed >= f64::MIN_POSITIVE && span.is_finite()) {
            return Err(InvalidParams(format!(
                "speed is {:?}: too slow for diameter {:?} and gap {:?} (the run would last \
                 beyond the doubles' range); use a speed above 1e-150 and at least \
                 (diameter + |gap|) * 1e-300",
                self.speed, self.diameter, self.gap
            )));
        }
        Ok(())
    }
}

/// What [`flypast_with_info`] achieved.
#[derive(Clone, Debug, PartialEq)]
pub struct FlypastInfo {
    /// The minimum distance between the two polygons over the motion, computed
    /// from the exact values of the generated doubles (the sign is exact, the
    /// magnitude rounded); negative: the relative path enters the Minkowski
    /// difference that deep, so the polygons collide.
    pub achieved_gap: f64,
    /// About when the polygons are closest.
    pub closest_time: f64,
}

/// The vertices of a regular `n`-gon of circumradius `radius` centred at the
/// origin, counter-clockwise, vertex `k` at angle `phase + 2πk/n` (computed
/// with `sin_cos` and rounded to doubles; such polygons stay strictly convex
/// in double precision far beyond `n = 2^20`).
pub fn regular_polygon(n: usize, radius: f64, phase: f64) -> Vec<[f64; 2]> {
    let step = TAU / n as f64;
    (0..n)
        .map(|k| {
            let (s, c) = (phase + step * k as f64).sin_cos();
            [radius * c, radius * s]
        })
        .collect()
}

/// Two congruent regular n-gons `A` and `B`: `B` passes `A` along a straight
/// line at minimum distance `gap` (see [`FlypastParams`]).
///
/// # Panics
///
/// If [`FlypastParams::check`] fails.
pub fn flypast(params: &FlypastParams) -> Scenario {
    flypast_with_info(params).0
}

/// [`flypast`], also returning the achieved minimum distance.
///
/// The distance from the relative path `r0 + t·w` (a line) to the Minkowski
/// difference `M = A ⊕ (−B)` is `(cross(w, r0) − max_{m∈M} cross(w, m)) / |w|`
/// when the line passes on the far side of `M`, and the maximum over `M` is
/// the sum of the support values of `A` and `−B` (O(n), no Minkowski sum is
/// built). It is evaluated exactly on the generated doubles, and `B` is nudged
/// by a few ulps if rounding made a requested miss touch or a requested
/// collision miss.
///
/// # Panics
///
/// If [`FlypastParams::check`] fails.
pub fn flypast_with_info(params: &FlypastParams) -> (Scenario, FlypastInfo) {
    check_or_panic(params.check());
    let mut rng = Rng::with_stream(params.seed, 1);
    let n = params.n;
    let d = params.diameter;
    let step = TAU / n as f64;
    let phase_a = rng.range_f64(0.05, 0.95) * step + 0.011_235_813;
    let theta = rng.range_f64(0.2, 0.8) * step;
    let a_body = regular_polygon(n, d / 2.0, phase_a);
    let b_body = regular_polygon(n, d / 2.0, phase_a + theta);
    let psi = rng.range_f64(0.15, PI / 2.0 - 0.15) + (rng.below(4) as f64) * (PI / 2.0);
    let w0 = [params.speed * psi.cos(), params.speed * psi.sin()];
    let (va, vb) = if params.a_moving {
        ([-w0[0] / 2.0, -w0[1] / 2.0], [w0[0] / 2.0, w0[1] / 2.0])
    } else {
        ([0.0, 0.0], w0)
    };
    // The exact relative velocity and its double approximation.
    let wr = [
        Dy::from_f64(vb[0]).sub(&Dy::from_f64(va[0])),
        Dy::from_f64(vb[1]).sub(&Dy::from_f64(va[1])),
    ];
    let w = [wr[0].to_f64(), wr[1].to_f64()];
    let wl2 = w[0] * w[0] + w[1] * w[1];
    let wl = wl2.sqrt();

    // max over M of cross(w, m) = max_a cross(w, a) - min_b cross(w, b).
    let max_m = exact_max_cross(&wr, w, &a_body, 1.0).add(&exact_max_cross(&wr, w, &b_body, -1.0));
    let max_m_f = max_m.to_f64();

    let tau = 1.5 * d / wl;
    let until = 2.0 * tau;
    let mut lambda = (max_m_f + params.gap * wl) / wl2;
    let place =
        |lambda: f64| -> [f64; 2] { [-tau * w[0] - lambda * w[1], -tau * w[1] + lambda * w[0]] };
    let want_hit = params.gap <= 0.0;
    let mut r0 = place(lambda);
    let mut delta = d * f64::EPSILON / wl.max(1e-300) * 0.25;
    let mut numerator = cross_dy(&wr, &r0).sub(&max_m);
    for _ in 0..400 {
        let hit = numerator.signum() <= 0;
        if hit == want_hit {
            break;
        }
        lambda += if want_hit { -delta } else { delta };
        delta *= 2.0;
        r0 = place(lambda);
        numerator = cross_dy(&wr, &r0).sub(&max_m);
    }
    let achieved_gap = numerator.to_f64() / wl;

    let scenario = Scenario {
        until,
        on_collision: params.mode,
        polygons: vec![
            PolygonSpec {
                id: "A".to_string(),
                vertices: a_body,
                position: [0.0, 0.0],
                velocity: va,
                fixed: !params.a_moving,
            },
            PolygonSpec {
                id: "B".to_string(),
                vertices: b_body,
                position: r0,
                velocity: vb,
                fixed: false,
            },
        ],
        flight_plan_changes: Vec::new(),
        ..Default::default()
    };
    (
        scenario,
        FlypastInfo {
            achieved_gap,
            closest_time: tau,
        },
    )
}

/// `max_i cross(w, sign * p_i)` exactly, with `w` exact (`wf` its double
/// approximation): doubles pick the candidates, exact arithmetic decides.
fn exact_max_cross(w: &[Dy; 2], wf: [f64; 2], pts: &[[f64; 2]], sign: f64) -> Dy {
    let vals: Vec<f64> = pts
        .iter()
        .map(|p| sign * (wf[0] * p[1] - wf[1] * p[0]))
        .collect();
    let best = vals.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let scale = (wf[0].abs() + wf[1].abs())
        * pts
            .iter()
            .map(|p| p[0].abs() + p[1].abs())
            .fold(0.0, f64::max);
    let tol = scale * 1e-12 + 1e-300;
    let mut out: Option<Dy> = None;
    for (p, v) in pts.iter().zip(&vals) {
        if *v >= best - tol {
            let c = cross_dy(w, p);
            let c = if sign < 0.0 { c.neg() } else { c };
            out = Some(match out {
                Some(o) if o.cmp_val(&c) >= 0 => o,
                _ => c,
            });
        }
    }
    out.expect("a polygon has vertices")
}

/// `cross(w, p)` exactly.
fn cross_dy(w: &[Dy; 2], p: &[f64; 2]) -> Dy {
    w[0].mul(&Dy::from_f64(p[1]))
        .sub(&w[1].mul(&Dy::from_f64(p[0])))
}

/// An exact dyadic number `m * 2^e`: every finite double is one, and sums,
/// differences and products stay exact.
#[derive(Clone, Debug)]
struct Dy {
    m: IBig,
    e: i32,
}

impl Dy {
    fn from_f64(x: f64) -> Dy {
        let (m, e) = crate::num::decompose_f64(x).expect("exact arithmetic on a non-finite number");
        Dy { m, e: e as i32 }
    }

    fn add(&self, o: &Dy) -> Dy {
        let e = self.e.min(o.e);
        let a = &self.m << (self.e - e) as usize;
        let b = &o.m << (o.e - e) as usize;
        Dy { m: a + b, e }
    }

    fn neg(&self) -> Dy {
        Dy {
            m: -self.m.clone(),
            e: self.e,
        }
    }

    fn sub(&self, o: &Dy) -> Dy {
        self.add(&o.neg())
    }

    fn mul(&self, o: &Dy) -> Dy {
        Dy {
            m: &self.m * &o.m,
            e: self.e + o.e,
        }
    }

    fn signum(&self) -> i32 {
        if self.m > IBig::ZERO {
            1
        } else if self.m < IBig::ZERO {
            -1
        } else {
            0
        }
    }

    fn cmp_val(&self, o: &Dy) -> i32 {
        self.sub(o).signum()
    }

    /// The nearest double, about (display and placement only).
    fn to_f64(&self) -> f64 {
        let mut x = self.m.to_f64().value();
        let mut e = self.e;
        while e > 0 {
            let k = e.min(1000);
            x *= 2f64.powi(k);
            e -= k;
        }
        while e < 0 {
            let k = e.max(-1000);
            x *= 2f64.powi(k);
            e -= k;
        }
        x
    }
}
