//! Issue 14, gear family: reproductions of the e → R cusp pole and `pole_window = 0`.

use cwsynth::mech::gear::*;
use cwsynth::synth::gear::*;
use std::f64::consts::TAU;

const R: f64 = 37.5e-3;
const RG: f64 = 1.25e-3;

fn pair(e: f64) -> GearPair {
    let c = EccentricCircle::new(R, e).unwrap();
    let cl = closing_center_distance(&c, 3, 1).unwrap();
    GearPair::new(c, RG, cl.a, 15.0).unwrap()
}

#[test]
fn repro_e_near_r() {
    let p = pair(37.49e-3);
    let s = singularities(&p, 24, 1e-13).unwrap();
    let n1 = s.poles.iter().filter(|q| q.which == Which::Mu1).count();
    println!("poles {} (mu1 {n1})", s.poles.len());
    for q in &s.poles {
        println!("{:?}", q);
    }
    for z in &s.zeros {
        if z.kind == ZeroKind::Indeterminate {
            println!("{:?}", z);
        }
    }
}
