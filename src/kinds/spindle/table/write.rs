//! Writing a spindle table: the preamble the reader ([`super`]) reads back, the header and one
//! row per sample, deterministically.

use super::super::record::Sensing;
use super::{ANGLE, RAD_PER_S_PER_RPM, REVOLUTION, SETUP, SPEED, SpindleTable, TIME, TITLE};
use crate::io::Conditions;
use crate::math::{M_PER_MM, M_PER_UM, RAD_PER_DEG, Real, fixed, trimmed};

/// The table as CSV text: the preamble (the conditions other than those the record states,
/// in their order, then `axis`, `samples_per_revolution` and each probe's `NAME_direction`,
/// `NAME_position_mm`, `NAME_sensing`), the header and one row per sample. The `setup` column
/// is written when a set-up has a name. Deterministic: the same table gives the same bytes, and
/// writing what this writes reads back gives the same bytes again. A record whose per-sample
/// vectors differ in length is written up to the shortest, and with a column for each probe
/// that has readings.
pub fn write_csv(table: &SpindleTable) -> String {
    let record = &table.record;
    let probe_keys: Vec<[String; 3]> = record
        .probes
        .iter()
        .map(|p| {
            [
                format!("{}_direction", p.name),
                format!("{}_position_mm", p.name),
                format!("{}_sensing", p.name),
            ]
        })
        .collect();
    let generated = |key: &str| {
        key == "axis"
            || key == "samples_per_revolution"
            || probe_keys.iter().flatten().any(|k| k == key)
    };
    let mut pairs: Vec<(String, String)> = table
        .conditions
        .keys()
        .filter(|k| !generated(k))
        .filter_map(|k| {
            table
                .conditions
                .get(k)
                .map(|(v, _)| (k.to_string(), v.to_string()))
        })
        .collect();
    pairs.push(("axis".into(), record.axis.letter().to_string()));
    pairs.push((
        "samples_per_revolution".into(),
        table.samples_per_revolution.to_string(),
    ));
    let join = |values: [Real; 3], decimals: usize| values.map(|v| trimmed(v, decimals)).join(" ");
    for (probe, [direction, position, sensing]) in record.probes.iter().zip(&probe_keys) {
        pairs.push((direction.clone(), join(probe.direction, 9)));
        pairs.push((
            position.clone(),
            join(probe.position.map(|v| v / M_PER_MM), 6),
        ));
        let kind = match probe.sensing {
            Sensing::Fixed => "fixed",
            Sensing::Rotating => "rotating",
        };
        pairs.push((sensing.clone(), kind.to_string()));
    }
    let mut text = Conditions::from_pairs(pairs).to_preamble(TITLE);

    let with_setup = record.setup.iter().any(|s| !s.is_empty());
    let mut n = record
        .angle
        .len()
        .min(record.revolution.len())
        .min(record.time.len())
        .min(record.speed.len());
    if with_setup {
        n = n.min(record.setup.len());
    }
    for values in &record.readings {
        n = n.min(values.len());
    }
    let mut header: Vec<String> = Vec::new();
    if with_setup {
        header.push(SETUP.into());
    }
    header.extend([REVOLUTION, ANGLE, TIME, SPEED].map(String::from));
    let columns = record.probes.len().min(record.readings.len());
    header.extend(
        record.probes[..columns]
            .iter()
            .map(|p| format!("{}_um", p.name)),
    );
    text += &header.join(",");
    text.push('\n');
    for i in 0..n {
        let mut fields: Vec<String> = Vec::with_capacity(header.len());
        if with_setup {
            fields.push(csv_text(&record.setup[i]));
        }
        fields.push(record.revolution[i].to_string());
        let mut angle = fixed(record.angle[i] / RAD_PER_DEG, 6);
        if angle == "360.000000" {
            // An angle within 5e-7° below 360° stays in [0, 360) once written.
            angle = "359.999999".into();
        }
        fields.push(angle);
        fields.push(fixed(record.time[i], 6));
        fields.push(fixed(record.speed[i] / RAD_PER_S_PER_RPM, 3));
        for values in &record.readings[..columns] {
            fields.push(fixed(values[i] / M_PER_UM, 6));
        }
        text += &fields.join(",");
        text.push('\n');
    }
    text
}

/// A text field as CSV: quoted when it holds a separator, a quote, a line break, or starts with
/// the comment mark.
fn csv_text(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) || text.starts_with('#') {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}
