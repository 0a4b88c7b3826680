//! The operating envelope's tables that every family with an envelope writes alike: the
//! sensitivity table (`crate::synth::envelope::sensitivities`) as
//! `<name>-envelope-sensitivity.csv`.

use super::Table;
use crate::synth::envelope::{End, Sensitivity};

/// The sensitivity table as `<name>-envelope-sensitivity.csv`: one row per interval end,
/// columns `parameter,end,at_si,derivative,derivative_error`.
pub fn sensitivity_table(rows: &[Sensitivity]) -> Table {
    let mut csv = String::from("parameter,end,at_si,derivative,derivative_error\n");
    for x in rows {
        let end = match x.end {
            End::Min => "min",
            End::Max => "max",
        };
        csv += &format!(
            "{},{end},{},{},{}\n",
            x.parameter, x.at, x.derivative, x.error
        );
    }
    Table {
        suffix: "envelope-sensitivity".into(),
        caption: "What each interval end costs: the optimised worst case's derivative with respect to it, from the optimum's multipliers (the objective's unit per rad/s, kg or m)".into(),
        csv,
    }
}
