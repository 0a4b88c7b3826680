//! `[[mechanism.mass_items]]` of a slider-crank file: itemised masses reduced to the slider
//! or the crank pin, each typed (`mass`) or taken from the part's drawing (`outline`, a plate
//! in a DXF file whose mass ρ·t·A is read by [`crate::problem::outline`]), summed into the
//! crank-pin and slider masses (`docs/problem-files.md`). Split from `file.rs` so the file's
//! sections and the mass items each stay readable.

use super::file_envelope::NamedMass;
use crate::families::slider_crank::synth as sc;
use crate::problem::outline::{self, OutlineRaw};
use crate::problem::{non_negative, FieldError};
use crate::units::{Length, Mass, Qty};
use serde::Deserialize;
use std::path::Path;

/// Most `[[mechanism.mass_items]]`.
pub const MAX_MASS_ITEMS: usize = 1000;

/// Where an itemised mass is reduced to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum MassAt {
    /// Moves with the slider.
    Slider,
    /// Turns with the crank pin.
    CrankPin,
}

/// `[[mechanism.mass_items]]`.
#[derive(Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MassItemRaw {
    /// Label.
    pub name: String,
    /// Mass (or `outline`; exactly one of the two).
    pub mass: Option<Qty<Mass>>,
    /// The item drawn as a plate in a DXF file (read relative to the problem file's folder):
    /// its mass is the plate's ρ·t·A. The item is lumped at the slider or the crank pin, so
    /// only the drawing's mass is used (not its centroid or inertia, and `origin` and `angle`
    /// change nothing). Not together with `mass`.
    pub outline: Option<OutlineRaw>,
    /// Reduced to.
    pub at: MassAt,
    /// Fraction of the mass reduced there (default 1; ½ for a boom resting on a sub-frame).
    pub fraction: Option<f64>,
}

/// A mass item resolved: its name, where it is reduced to, its whole mass (kg, typed or
/// drawn), the fraction reduced there and, when drawn, where the mass came from.
#[derive(Debug, Clone, PartialEq)]
pub struct MassItem {
    /// `name`.
    pub name: String,
    /// `at`.
    pub at: MassAt,
    /// The item's mass (kg): `mass`, or the drawing's ρ·t·A.
    pub mass: f64,
    /// `fraction` (default 1).
    pub fraction: f64,
    /// The drawing its mass was read from (`outline`), if any.
    pub drawn: Option<DrawnMass>,
}

/// Where a drawn mass item's mass came from (the result's `model.mass_items_from_drawings`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DrawnMass {
    /// The item's `name`.
    pub item: String,
    /// The drawing, as the problem file names it (relative to its folder).
    pub file: String,
    /// The layer read (`None`: every layer).
    pub layer: Option<String>,
    /// A, the outline's area (m²).
    pub area_m2: f64,
    /// t (m).
    pub thickness_m: f64,
    /// ρ (kg/m³).
    pub density_kg_m3: f64,
    /// ρ·t·A (kg), the item's whole mass (before its fraction).
    pub mass_kg: f64,
}

/// The `[mechanism]` keys the link masses come from.
pub(super) struct LinkMassKeys<'a> {
    /// `crank_mass`.
    pub crank_mass: Option<Qty<Mass>>,
    /// `slider_mass`.
    pub slider_mass: Option<Qty<Mass>>,
    /// `crank_centroid`.
    pub crank_centroid: Option<Qty<Length>>,
    /// `[[mechanism.mass_items]]`.
    pub mass_items: &'a [MassItemRaw],
}

/// The crank-pin mass m₂, the slider mass m₄, the crank's centroid radius r₂ and the items:
/// given (r₂ = R/2 by default, no items), or summed from `[[mechanism.mass_items]]` (each
/// item's fraction of its mass at the crank pin or at the slider; r₂ = R), drawings read from
/// `dir`.
pub(super) fn resolve_link_masses(
    m: &LinkMassKeys,
    r: f64,
    dir: &Path,
) -> Result<(f64, f64, f64, Vec<MassItem>), FieldError> {
    if m.mass_items.is_empty() {
        let need = |q: Option<Qty<Mass>>, f: &str| {
            q.map(|q| q.si()).ok_or_else(|| {
                FieldError::new(
                    f,
                    "missing: give it, or itemise the masses in [[mechanism.mass_items]]",
                )
            })
        };
        let m2 = non_negative(
            "mechanism.crank_mass",
            need(m.crank_mass, "mechanism.crank_mass")?,
        )?;
        let m4 = non_negative(
            "mechanism.slider_mass",
            need(m.slider_mass, "mechanism.slider_mass")?,
        )?;
        let r2 = non_negative(
            "mechanism.crank_centroid",
            m.crank_centroid.map_or(0.5 * r, |q| q.si()),
        )?;
        return Ok((m2, m4, r2, Vec::new()));
    }
    for (q, f) in [
        (m.crank_mass, "mechanism.crank_mass"),
        (m.slider_mass, "mechanism.slider_mass"),
    ] {
        if q.is_some() {
            return Err(FieldError::new(
                f,
                "given together with mechanism.mass_items; allowed: one or the other",
            ));
        }
    }
    if m.crank_centroid.is_some() {
        return Err(FieldError::new(
            "mechanism.crank_centroid",
            "itemised crank-pin masses are at the crank pin (r2 = R); remove crank_centroid",
        ));
    }
    if m.mass_items.len() > MAX_MASS_ITEMS {
        return Err(FieldError::new(
            format!("mechanism.mass_items[{MAX_MASS_ITEMS}]"),
            format!(
                "{} items; allowed: at most {MAX_MASS_ITEMS}",
                m.mass_items.len()
            ),
        ));
    }
    let items = m
        .mass_items
        .iter()
        .enumerate()
        .map(|(i, it)| resolve_item(it, &format!("mechanism.mass_items[{i}]"), dir))
        .collect::<Result<Vec<_>, _>>()?;
    let (mut pin, mut slider) = (0.0, 0.0);
    for it in &items {
        match it.at {
            MassAt::CrankPin => pin += it.fraction * it.mass,
            MassAt::Slider => slider += it.fraction * it.mass,
        }
    }
    Ok((pin, slider, r, items))
}

/// One mass item at `key` (`mechanism.mass_items[i]`): exactly one of `mass` and `outline`
/// (its drawing read from `dir`), and 0 ≤ fraction ≤ 1.
fn resolve_item(it: &MassItemRaw, key: &str, dir: &Path) -> Result<MassItem, FieldError> {
    let (mass, drawn) = match (&it.mass, &it.outline) {
        (Some(q), None) => (non_negative(&format!("{key}.mass"), q.si())?, None),
        (given, Some(o)) => {
            outline::set_by(key, &[("mass", given.is_some())], outline::OUTLINE_SETS)?;
            let p = outline::plate(o, dir, &format!("{key}.outline"))?;
            let drawn = DrawnMass {
                item: it.name.clone(),
                file: o.file.clone(),
                layer: o.layer.clone(),
                area_m2: p.area,
                thickness_m: o.thickness.si(),
                density_kg_m3: o.density.si(),
                mass_kg: p.mass,
            };
            (p.mass, Some(drawn))
        }
        (None, None) => {
            return Err(FieldError::new(
                format!("{key}.mass"),
                "missing: the item's mass; allowed: mass = \"… kg\", or outline = { file = \"….dxf\", thickness = \"… mm\", density = \"… kg/m^3\" }",
            ))
        }
    };
    let fraction = it.fraction.unwrap_or(1.0);
    if !(0.0..=1.0).contains(&fraction) {
        return Err(FieldError::new(
            format!("{key}.fraction"),
            format!("got {fraction}; allowed: 0 ≤ fraction ≤ 1"),
        ));
    }
    let item = MassItem {
        name: it.name.clone(),
        at: it.at,
        mass,
        fraction,
        drawn,
    };
    Ok(item)
}

/// The items as the envelope sees them (`of = "<item name>"`).
pub(super) fn named_masses(items: &[MassItem]) -> Vec<NamedMass<'_>> {
    items
        .iter()
        .map(|it| NamedMass {
            name: &it.name,
            of: match it.at {
                MassAt::Slider => sc::MassOf::Slider,
                MassAt::CrankPin => sc::MassOf::CrankPin,
            },
            mass: it.mass,
            fraction: it.fraction,
        })
        .collect()
}
