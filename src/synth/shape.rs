//! The counterweight as a real part: an annular-sector plate of given material and
//! thickness that realises a required unbalance inside an envelope on the lever.
//!
//! A sector of inner radius rᵢ, outer radius rₒ and angle θ (symmetric about the
//! counterweight's direction), thickness t and density ρ has
//!
//! * area A = (θ/2)(rₒ² − rᵢ²), mass m = ρ t A, volume V = t A;
//! * centroid radius r_c = 4 sin(θ/2)(rₒ³ − rᵢ³) / (3θ (rₒ² − rᵢ²));
//! * unbalance U = m r_c = (2/3) ρ t sin(θ/2) (rₒ³ − rᵢ³);
//! * moment of inertia about the crank axis I = ρ t (θ/4)(rₒ⁴ − rᵢ⁴).
//!
//! *Least outer radius*: U is largest for rᵢ = rᵢ,min and θ* = min(θ_max, π), so
//! rₒ = ∛(rᵢ,min³ + 3U / (2ρt sin(θ*/2))) in closed form.
//! *Least mass*: for a given θ, material as far out as allowed (rₒ = rₒ,max) and rᵢ from
//! U = U_req; the mass is then a 1-D function of θ, minimised by argmin's Brent search.

use crate::numeric::{brent_root, minimize_1d};
use std::f64::consts::PI;

/// What the shape minimises.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    Default,
    schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum ShapeGoal {
    /// The lightest plate.
    #[default]
    Mass,
    /// The smallest outer radius (the most compact machine).
    OuterRadius,
}

/// Material, thickness and envelope of the plate (SI).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ShapeSpec {
    /// ρ (kg/m³).
    pub density: f64,
    /// t (m).
    pub thickness: f64,
    /// Smallest inner radius (m): clearance to the hub or crank pin.
    pub inner_radius_min: f64,
    /// Largest outer radius (m): the envelope.
    pub outer_radius_max: f64,
    /// Largest sector angle θ (rad), at most 2π.
    pub max_angle: f64,
    /// Objective.
    pub goal: ShapeGoal,
}

/// A plate.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Sector {
    /// rᵢ (m).
    pub inner_radius_m: f64,
    /// rₒ (m).
    pub outer_radius_m: f64,
    /// θ (rad).
    pub angle_rad: f64,
    /// m (kg).
    pub mass_kg: f64,
    /// r_c (m).
    pub centroid_radius_m: f64,
    /// V (m³).
    pub volume_m3: f64,
    /// I about the crank axis (kg·m²).
    pub inertia_kgm2: f64,
    /// U = m r_c (kg·m).
    pub unbalance_kgm: f64,
}

impl Sector {
    /// The sector's figures from its dimensions.
    pub fn new(spec: &ShapeSpec, ri: f64, ro: f64, theta: f64) -> Sector {
        let rt = spec.density * spec.thickness;
        let area = 0.5 * theta * (ro * ro - ri * ri);
        let u = 2.0 / 3.0 * rt * (0.5 * theta).sin() * (ro.powi(3) - ri.powi(3));
        let mass = rt * area;
        Sector {
            inner_radius_m: ri,
            outer_radius_m: ro,
            angle_rad: theta,
            mass_kg: mass,
            centroid_radius_m: if mass > 0.0 { u / mass } else { 0.0 },
            volume_m3: spec.thickness * area,
            inertia_kgm2: rt * 0.25 * theta * (ro.powi(4) - ri.powi(4)),
            unbalance_kgm: u,
        }
    }
}

/// The outcome of [`design`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "kebab-case", tag = "status")]
pub enum ShapeOutcome {
    /// A plate found.
    Found {
        /// The plate.
        sector: Sector,
        /// How it was found.
        method: String,
    },
    /// The envelope cannot hold a plate with this unbalance.
    Infeasible {
        /// Why, with the largest unbalance the envelope allows.
        reason: String,
    },
}

impl ShapeSpec {
    /// The largest unbalance the envelope holds, U_max = (2/3) ρ t sin(θ*/2)(rₒ,max³ − rᵢ,min³)
    /// with θ* = min(θ_max, π) (kg·m): the whole annular sector of half-angle θ*/2.
    pub fn max_unbalance(&self) -> f64 {
        let theta_star = self.max_angle.min(PI);
        2.0 / 3.0
            * self.density
            * self.thickness
            * (0.5 * theta_star).sin()
            * (self.outer_radius_max.powi(3) - self.inner_radius_min.powi(3))
    }
}

/// Finds the plate realising the unbalance `u` (kg·m).
pub fn design(spec: &ShapeSpec, u: f64) -> ShapeOutcome {
    let rt = spec.density * spec.thickness;
    let (ri0, ro_max) = (spec.inner_radius_min, spec.outer_radius_max);
    let theta_star = spec.max_angle.min(PI);
    let u_max = spec.max_unbalance();
    if !(u <= u_max) {
        return ShapeOutcome::Infeasible {
            reason: format!(
                "the envelope (r_i ≥ {ri0} m, r_o ≤ {ro_max} m, θ ≤ {:.1}°) holds at most U = {u_max:.6} kg·m at this thickness; U = {u:.6} kg·m needs a plate at least {:.4} m thick",
                spec.max_angle.to_degrees(),
                spec.thickness * u / u_max
            ),
        };
    }
    if u <= 0.0 {
        return ShapeOutcome::Found {
            sector: Sector::new(spec, ri0, ri0, 0.0),
            method: "no unbalance: no plate".into(),
        };
    }
    match spec.goal {
        ShapeGoal::OuterRadius => {
            let ro = (ri0.powi(3) + 3.0 * u / (2.0 * rt * (0.5 * theta_star).sin())).cbrt();
            ShapeOutcome::Found {
                sector: Sector::new(spec, ri0, ro, theta_star),
                method: "closed form: r_i at its minimum, θ = min(θ_max, 180°), r_o = ∛(r_i³ + 3U/(2ρt sin(θ/2)))".into(),
            }
        }
        ShapeGoal::Mass => {
            // rᵢ(θ) from U with rₒ = rₒ,max; feasible where rᵢ ≥ rᵢ,min, i.e. sin(θ/2) ≥ c.
            let c = 3.0 * u / (2.0 * rt * (ro_max.powi(3) - ri0.powi(3)));
            let theta_lo = 2.0 * c.min(1.0).asin();
            let ri_of = |theta: f64| {
                (ro_max.powi(3) - 3.0 * u / (2.0 * rt * (0.5 * theta).sin()))
                    .max(0.0)
                    .cbrt()
                    .max(ri0)
            };
            let mass = |theta: f64| Sector::new(spec, ri_of(theta), ro_max, theta).mass_kg;
            let hi = theta_star.max(theta_lo);
            let best = minimize_1d(mass, theta_lo, hi, 1e-12).ok();
            let theta = best.map(|b| b.x).unwrap_or(hi);
            let ri = ri_of(theta);
            let sector = Sector::new(spec, ri, ro_max, theta);
            ShapeOutcome::Found {
                sector,
                method: format!(
                    "r_o at the envelope, r_i from U, θ by argmin's Brent search on [{:.4}, {:.4}] rad ({} evaluations)",
                    theta_lo,
                    hi,
                    best.map(|b| b.evals).unwrap_or(0)
                ),
            }
        }
    }
}

/// The annular sector (rᵢ, rₒ, θ) about an axis that is one body of mass `m` with centroid
/// radius `rc` and moment of inertia `i_axis` about the axis, all of it within `r_max`:
/// I = (m/2)(rᵢ² + rₒ²) and r_c = 4 sin(θ/2)(rₒ³ − rᵢ³)/(3θ(rₒ² − rᵢ²)). The sector is as
/// far out as the envelope allows (rₒ = r_max, rᵢ = √(2I/m − r_max²)) when I ≥ m r_max²/2,
/// else a full-radius sector rᵢ = 0, rₒ = √(2I/m); θ then follows from r_c (r_c falls
/// monotonically from (2/3)(rₒ³ − rᵢ³)/(rₒ² − rᵢ²) at θ → 0 to 0 at 2π; Brent). `None` when
/// no sector realises the three figures (I > m r_max², or r_c beyond the θ → 0 limit).
pub fn sector_realising(m: f64, rc: f64, i_axis: f64, r_max: f64) -> Option<(f64, f64, f64)> {
    if !(m > 0.0 && i_axis >= 0.0 && rc >= 0.0) {
        return None;
    }
    let s2 = 2.0 * i_axis / m; // rᵢ² + rₒ²
    let (ri, ro) = if s2 >= r_max * r_max {
        let ri2 = s2 - r_max * r_max;
        if ri2 > r_max * r_max * (1.0 + 1e-12) {
            return None;
        }
        (ri2.max(0.0).sqrt().min(r_max), r_max)
    } else {
        (0.0, s2.sqrt())
    };
    if ro <= 0.0 {
        return (rc == 0.0).then_some((0.0, 0.0, 0.0));
    }
    let k = if ro - ri <= 1e-15 * ro {
        ro // a thin arc: (2/3)(ro³−ri³)/(ro²−ri²) → ro
    } else {
        2.0 / 3.0 * (ro.powi(3) - ri.powi(3)) / (ro * ro - ri * ri)
    };
    let centroid = |th: f64| k * (0.5 * th).sin() / (0.5 * th);
    if rc > k * (1.0 + 1e-12) {
        return None;
    }
    if rc <= 0.0 {
        return Some((ri, ro, 2.0 * PI));
    }
    let th = brent_root(|th| centroid(th) - rc, 1e-12, 2.0 * PI, 1e-14)
        .map(|r| r.x)
        .unwrap_or(1e-12);
    Some((ri, ro, th))
}
