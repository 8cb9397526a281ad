//! What each table adds to a rotary axis's component errors, order by order: the tables in the
//! order given, each added to those before it, and for every component series (EXC, EBC, ECC …)
//! and Fourier order whether all its coefficients are identifiable then, with the readings so
//! far. So a report says which set-up reveals which order (what a second sphere height adds,
//! what a second radius adds), as `tests/it/estimate/rotary_components.rs` derives by hand.

use crate::estimate::Readings;
use crate::estimate::fit::{self, Problem};
use crate::estimate::identifiability::{Options, analyse};
use crate::estimate::spec::{ParameterSet, is_rotary_component};
use crate::machine::Machine;

/// The verdicts, order by order, as the tables add up.
#[derive(Clone, Debug, PartialEq)]
pub struct ByOrder {
    /// Per table in the order given: its name and the readings of it and those before it.
    pub columns: Vec<(String, usize)>,
    /// Per component series and order (`EXC`, 2): whether every coefficient of it is
    /// identifiable from the tables up to each column.
    pub rows: Vec<(String, usize, Vec<bool>)>,
}

/// The verdicts for the rotary components in `set` from `sets` on `machine` (see the module
/// documentation); `None` when `set` has none, or a prefix of the tables makes no problem.
pub fn by_order(machine: &Machine, set: &ParameterSet, sets: &[Readings]) -> Option<ByOrder> {
    let parameters = set.model.parameters();
    // (series, order) of each free coefficient that is a rotary component's.
    let keys: Vec<Option<(String, usize)>> = (0..set.len())
        .map(|j| {
            let parameter = &parameters[set.owner[j]];
            is_rotary_component(parameter.name).then(|| {
                let series = set.labels[j].split('.').next().unwrap_or_default();
                (series.to_string(), set.degree[j])
            })
        })
        .collect();
    let mut rows: Vec<(String, usize, Vec<bool>)> = Vec::new();
    for (series, order) in keys.iter().flatten() {
        if !rows.iter().any(|(s, o, _)| s == series && o == order) {
            rows.push((series.clone(), *order, Vec::new()));
        }
    }
    if rows.is_empty() {
        return None;
    }
    rows.sort_by(|a, b| a.1.cmp(&b.1).then(a.0.cmp(&b.0)));
    let mut columns = Vec::new();
    let mut readings = 0;
    for k in 0..sets.len() {
        readings += sets[k].len();
        let name = std::path::Path::new(&sets[k].source)
            .file_name()
            .map_or_else(|| sets[k].source.clone(), |n| n.to_string_lossy().into());
        columns.push((name, readings));
        let problem = Problem::new(machine, set, &sets[..=k]).ok()?;
        let design = fit::profiled_design(&problem);
        let identified = analyse(&design, &set.labels, &Options::default()).standard_uncertainty;
        for (series, order, verdicts) in &mut rows {
            let all = (0..set.len())
                .filter(|&j| keys[j].as_ref() == Some(&(series.clone(), *order)))
                .all(|j| identified[j].is_some());
            verdicts.push(all);
        }
    }
    Some(ByOrder { columns, rows })
}

impl ByOrder {
    /// A table for people: a row per series and order, a column per table added.
    pub fn text(&self) -> String {
        let mut cells: Vec<Vec<String>> = Vec::new();
        let mut header = vec!["order".to_string(), "series".into()];
        let mut counts = vec![String::new(), "readings".into()];
        for (k, (name, readings)) in self.columns.iter().enumerate() {
            header.push(if k == 0 {
                name.clone()
            } else {
                format!("+ {name}")
            });
            counts.push(readings.to_string());
        }
        cells.push(header);
        cells.push(counts);
        for (series, order, verdicts) in &self.rows {
            let mut row = vec![order.to_string(), series.clone()];
            row.extend(
                verdicts
                    .iter()
                    .map(|&v| if v { "yes" } else { "no" }.to_string()),
            );
            cells.push(row);
        }
        let mut out = String::from(
            "rotary components by order, as the tables add up (yes: every coefficient of that order identifiable):\n",
        );
        for line in crate::estimate::plan::table(&cells).lines() {
            out += &format!("  {line}\n");
        }
        out
    }

    /// For `estimate.json`: `tables` ({`table`, `readings`} each, cumulative) and `orders`
    /// ({`series`, `order`, `identifiable`: one verdict per table} each).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "tables": self.columns.iter().map(|(name, readings)| serde_json::json!({
                "table": name,
                "readings": readings,
            })).collect::<Vec<_>>(),
            "orders": self.rows.iter().map(|(series, order, verdicts)| serde_json::json!({
                "series": series,
                "order": order,
                "identifiable": verdicts,
            })).collect::<Vec<_>>(),
        })
    }
}
