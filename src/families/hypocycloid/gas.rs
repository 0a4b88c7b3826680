//! The gas force of an ideal single-acting compressor cycle on the piston of the
//! hypocycloidal machine, and its drive torque. The paper's machine is a compressor; its
//! drive torque is the gas torque plus the inertia torque of the mechanism.
//!
//! The head is at +x (the piston's top dead centre is S_max): the cylinder volume is
//! V(φ) = V_c + A_p (S_max − S(φ)), A_p = πD²/4, V_c = ε·A_p·stroke (ε the clearance
//! ratio). Ideal valves: while both are shut the gas follows p V^n = const from the state
//! at the last closing; the suction valve holds p = p_s while the volume grows below p_s,
//! the discharge valve holds p = p_d while it shrinks above p_d. This valve logic follows
//! V(φ) through any number of reversals (variant 1's dwell splits the bottom dead centre
//! into two), which a four-stroke description (expansion, suction, compression, discharge)
//! would not.
//!
//! The force of the gas on the piston is −(p − p_b) A_p e_x (p_b the pressure behind the
//! piston), so the drive torque at constant speed is
//!
//!   T_gas(φ) = (p(φ) − p_b) A_p dS/dφ,
//!
//! and its mean over a turn times 2π is the indicated work −∮ p dV (the constant p_b does no
//! work over a cycle).

use crate::families::hypocycloid::model::Hypocycloid;
use crate::numeric::{brent_root, periodic_peak};
use std::f64::consts::{PI, TAU};

/// The cycle data (SI).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct GasCycle {
    /// D, the bore (m).
    pub bore: f64,
    /// ε = V_c/V_s, the clearance volume over the swept volume.
    pub clearance_ratio: f64,
    /// p_s, suction pressure (Pa, absolute).
    pub suction: f64,
    /// p_d, discharge pressure (Pa, absolute).
    pub discharge: f64,
    /// n, the polytropic exponent of compression and re-expansion (1 ≤ n ≤ 2).
    pub exponent: f64,
    /// p_b, the pressure behind the piston (Pa, absolute).
    pub back: f64,
}

/// A named load case (`[[mechanism.load_cases]]`): the nominal cycle with the pressures the
/// case changes (`load_cases.rs`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LoadCase {
    /// Its name.
    pub name: String,
    /// Its cycle.
    pub gas: GasCycle,
}

/// Why a cycle cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GasError {
    /// The piston path could not be analysed.
    #[error("{0}")]
    Mech(#[from] crate::families::hypocycloid::model::MechError),
    /// A dead centre or a valve event could not be located.
    #[error("valve event search failed: {0}")]
    Search(#[from] crate::numeric::SearchError),
}

/// One piece of the turn on which p(φ) is smooth: [φ0, φ1] and the law of p there.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Piece {
    /// Start angle (rad, unwrapped from the top dead centre).
    pub phi0: f64,
    /// End angle (rad).
    pub phi1: f64,
    /// p = p_ref (V_ref/V)^n with (p_ref, V_ref), or a constant p_ref when `v_ref` is 0
    /// (a valve open).
    pub p_ref: f64,
    /// V_ref (m³), 0 for a constant pressure.
    pub v_ref: f64,
}

/// The cycle over one turn from the top dead centre.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Cycle {
    /// The data.
    pub data: GasCycle,
    /// A_p (m²).
    pub area: f64,
    /// S_max (m, from O), the top dead centre.
    pub s_top: f64,
    /// Stroke (m).
    pub stroke: f64,
    /// V_c (m³).
    pub v_clearance: f64,
    /// φ of the top dead centre (rad).
    pub phi_top: f64,
    /// The smooth pieces, φ increasing from `phi_top` to `phi_top` + 2π.
    pub pieces: Vec<Piece>,
    /// Whether the compression reaches p_d (else nothing is delivered).
    pub delivers: bool,
}

/// 16-point Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_16).
fn gauss_legendre() -> [(f64, f64); 16] {
    let n = 16;
    let mut out = [(0.0, 0.0); 16];
    for (i, o) in out.iter_mut().enumerate() {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        *o = (x, 2.0 / ((1.0 - x * x) * dp * dp));
    }
    out
}

impl Cycle {
    /// The cycle of `data` on the piston path of `m` with carrier length R (m).
    pub fn new(m: &Hypocycloid, r_carrier: f64, data: GasCycle) -> Result<Cycle, GasError> {
        let st = m.stroke()?;
        let s_of = |p: f64| r_carrier * m.piston(p).s_rel;
        let s_top = s_of(st.phi_top);
        let stroke = r_carrier * st.stroke;
        let area = PI * data.bore * data.bore / 4.0;
        let v_clearance = data.clearance_ratio * area * stroke;
        let vol = |p: f64| v_clearance + area * (s_top - s_of(p));
        // The dead centres: the zeros of dS/dφ, bracketed on a fine scan and refined.
        let n = 720;
        let h = TAU / n as f64;
        let p0 = st.phi_top;
        let ds = |p: f64| m.piston(p).ds;
        let mut ends = vec![p0];
        for k in 0..n {
            let (a, b) = (p0 + k as f64 * h, p0 + (k + 1) as f64 * h);
            let (fa, fb) = (ds(a), ds(b));
            if k > 0 && fa == 0.0 {
                ends.push(a);
            } else if fa * fb < 0.0 && k + 1 < n {
                ends.push(brent_root(ds, a, b, 1e-14)?.x);
            }
        }
        ends.push(p0 + TAU);
        // Two turns of the valve logic; the second is periodic.
        let nexp = data.exponent;
        let mut state = (data.discharge, v_clearance);
        let mut pieces = Vec::new();
        let mut delivers = false;
        for turn in 0..2 {
            pieces.clear();
            delivers = false;
            for w in ends.windows(2) {
                let (a, b) = (w[0], w[1]);
                let (va, vb) = (vol(a), vol(b));
                let grows = vb > va;
                let (p_ref, v_ref) = state;
                let closed = |v: f64| p_ref * (v_ref / v).powf(nexp);
                let limit = if grows { data.suction } else { data.discharge };
                let beyond = |p: f64| if grows { p <= limit } else { p >= limit };
                if beyond(closed(va)) {
                    // The valve is open from the start of the segment.
                    pieces.push(Piece {
                        phi0: a,
                        phi1: b,
                        p_ref: limit,
                        v_ref: 0.0,
                    });
                    state = (limit, vb);
                    delivers |= !grows;
                } else if beyond(closed(vb)) {
                    // It opens inside: V* = V_ref (p_ref/limit)^(1/n).
                    let vs = v_ref * (p_ref / limit).powf(1.0 / nexp);
                    let ev = brent_root(|p| vol(p) - vs, a, b, 1e-14)?.x;
                    pieces.push(Piece {
                        phi0: a,
                        phi1: ev,
                        p_ref,
                        v_ref,
                    });
                    pieces.push(Piece {
                        phi0: ev,
                        phi1: b,
                        p_ref: limit,
                        v_ref: 0.0,
                    });
                    state = (limit, vb);
                    delivers |= !grows;
                } else {
                    pieces.push(Piece {
                        phi0: a,
                        phi1: b,
                        p_ref,
                        v_ref,
                    });
                }
            }
            let _ = turn;
        }
        Ok(Cycle {
            data,
            area,
            s_top,
            stroke,
            v_clearance,
            phi_top: p0,
            pieces,
            delivers,
        })
    }

    /// V(φ) (m³) on the path of `m`.
    pub fn volume(&self, m: &Hypocycloid, r_carrier: f64, phi: f64) -> f64 {
        self.v_clearance + self.area * (self.s_top - r_carrier * m.piston(phi).s_rel)
    }

    /// The piece holding φ (any angle).
    fn piece(&self, phi: f64) -> &Piece {
        let u = self.phi_top + (phi - self.phi_top).rem_euclid(TAU);
        self.pieces
            .iter()
            .find(|p| u <= p.phi1)
            .unwrap_or_else(|| self.pieces.last().expect("at least one piece"))
    }

    /// p(φ) (Pa).
    pub fn pressure(&self, m: &Hypocycloid, r_carrier: f64, phi: f64) -> f64 {
        let pc = self.piece(phi);
        if pc.v_ref == 0.0 {
            pc.p_ref
        } else {
            pc.p_ref * (pc.v_ref / self.volume(m, r_carrier, phi)).powf(self.data.exponent)
        }
    }

    /// T_gas(φ) = (p − p_b) A_p dS/dφ (N·m).
    pub fn torque(&self, m: &Hypocycloid, r_carrier: f64, phi: f64) -> f64 {
        (self.pressure(m, r_carrier, phi) - self.data.back)
            * self.area
            * r_carrier
            * m.piston(phi).ds
    }

    /// The mean of `f` over the turn: 16-point Gauss–Legendre on `sub` equal parts of every
    /// smooth piece (the valve events and dead centres are the pieces' ends, so the
    /// integrand is smooth inside each), and the change from `sub`/2 parts as its error.
    pub fn mean_over_pieces(&self, f: &dyn Fn(f64) -> f64, sub: usize) -> (f64, f64) {
        let gl = gauss_legendre();
        let integral = |k: usize| -> f64 {
            let mut s = 0.0;
            for pc in &self.pieces {
                let h = (pc.phi1 - pc.phi0) / k as f64;
                for j in 0..k {
                    let (a, b) = (pc.phi0 + j as f64 * h, pc.phi0 + (j + 1) as f64 * h);
                    let (c, r) = (0.5 * (a + b), 0.5 * (b - a));
                    s += r * gl.iter().map(|&(x, w)| w * f(c + r * x)).sum::<f64>();
                }
            }
            s / TAU
        };
        let sub = sub.max(2);
        let fine = integral(sub);
        let coarse = integral(sub / 2);
        (fine, (fine - coarse).abs())
    }

    /// The peak of |p(φ) − p_b|·A_p, the gas force on the piston (N), by the refined scan.
    pub fn peak_force(&self, m: &Hypocycloid, r_carrier: f64) -> f64 {
        periodic_peak(
            |p| (self.pressure(m, r_carrier, p) - self.data.back).abs() * self.area,
            720,
            1e-10,
        )
        .map(|p| p.peak.fx)
        .unwrap_or(f64::NAN)
    }
}
