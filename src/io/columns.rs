//! Columns a reader has no use for. A real export carries more than the figures need (a
//! status flag, the operator, the date, the humidity, the carriage's X and Y): such a column
//! is read past, listed in the report as not read, and no figure depends on it. A column
//! that looks like one the reader *does* read — the same name in another case or with the
//! unit in brackets (`Deviation (µm)`), the same quantity in another unit (`deviation_nm`,
//! `time_h`), a misspelling (`deviaton_um`), a channel without its unit (`x`) or a
//! thermometer named another way (`temp_c`) — is refused by name instead: reading past it
//! would drop the data the user meant to give, or evaluate them in the wrong unit.

/// Units by quantity, as they follow the last `_` of a column name (after [`normalise`]).
const LENGTH: [&str; 11] = [
    "nm", "um", "mm", "cm", "m", "in", "inch", "mil", "thou", "micron", "microns",
];
const ANGLE: [&str; 9] = [
    "rad", "mrad", "urad", "deg", "degree", "degrees", "arcsec", "arcmin", "asec",
];
const TIME: [&str; 8] = ["s", "sec", "ms", "min", "mins", "h", "hr", "hours"];
const TEMPERATURE: [&str; 5] = ["c", "degc", "f", "degf", "celsius"];
const SPEED: [&str; 3] = ["rpm", "hz", "rps"];

/// A physical quantity a column's unit measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Quantity {
    Length,
    Angle,
    Time,
    Temperature,
    Speed,
}

/// The quantity `unit` (a column name's last `_` part, normalised) measures, if it is a unit.
pub(crate) fn quantity(unit: &str) -> Option<Quantity> {
    [
        (Quantity::Length, &LENGTH[..]),
        (Quantity::Angle, &ANGLE[..]),
        (Quantity::Time, &TIME[..]),
        (Quantity::Temperature, &TEMPERATURE[..]),
        (Quantity::Speed, &SPEED[..]),
    ]
    .into_iter()
    .find(|(_, units)| units.contains(&unit))
    .map(|(q, _)| q)
}

/// A column name as the readers spell theirs: lower case, `µ` as `u`, every run of other
/// characters (spaces, brackets, `-`, `/`) one `_`, none at either end: `Deviation (µm)`
/// becomes `deviation_um`.
pub(crate) fn normalise(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for c in name.chars().flat_map(char::to_lowercase) {
        let c = if c == 'µ' || c == 'μ' { 'u' } else { c };
        if c.is_ascii_alphanumeric() {
            out.push(c);
        } else if !out.is_empty() && !out.ends_with('_') {
            out.push('_');
        }
    }
    while out.ends_with('_') {
        out.pop();
    }
    out
}

/// Why `name`, a column the reader does not read, looks like one of `known` (the reader's
/// fixed column names): the message refusing it, or `None` when it is simply another column.
pub(crate) fn looks_like(name: &str, known: &[&str]) -> Option<String> {
    let n = normalise(name);
    if let Some(k) = known.iter().find(|k| **k == n) {
        return Some(format!(
            "column `{name}`: this reader reads `{k}` (lower case, the unit after `_`); rename the column"
        ));
    }
    let split = |s: &str| {
        s.rsplit_once('_')
            .map(|(stem, unit)| (stem.to_string(), unit.to_string()))
    };
    if let Some((stem, unit)) = split(&n)
        && let Some(q) = quantity(&unit)
        && let Some(k) = known
            .iter()
            .find(|k| split(k).is_some_and(|(ks, ku)| ks == stem && quantity(&ku) == Some(q)))
    {
        return Some(format!(
            "column `{name}` is in {unit}, but this reader reads it as `{k}`; convert the values and rename the column"
        ));
    }
    if let Some(k) = known
        .iter()
        .find(|k| split(k).is_some_and(|(ks, ku)| ks == n && quantity(&ku).is_some()))
    {
        return Some(format!(
            "column `{name}` has no unit: this reader reads `{k}`"
        ));
    }
    known
        .iter()
        .find(|k| {
            let limit = match k.len() {
                0..5 => 0,
                5..8 => 1,
                _ => 2,
            };
            limit > 0 && edit_distance(&n, k) <= limit
        })
        .map(|k| format!("column `{name}`: did you mean `{k}`?"))
}

/// The columns among `unread` (a header's names its reader has no use for, in order) that are
/// read past; the first that `slip` says looks like one the reader does read is refused at
/// the header's `line`, with what the reader reads (`reads`).
pub(crate) fn read_past<'a>(
    unread: impl IntoIterator<Item = &'a str>,
    slip: impl Fn(&str) -> Option<String>,
    reads: &str,
    line: u64,
    file: &str,
) -> Result<Vec<String>, super::TableError> {
    unread
        .into_iter()
        .map(|name| match slip(name) {
            Some(message) => Err(super::TableError::new(
                file,
                Some(line),
                format!("{message} (this reader reads {reads})"),
            )),
            None => Ok(name.to_string()),
        })
        .collect()
}

/// Why `name` looks like a thermometer's column written another way than `temp_<sensor>_degc`,
/// for readers that read thermometers; `None` when it does not.
pub(crate) fn thermometer_slip(name: &str) -> Option<String> {
    let n = normalise(name);
    let sensor = n
        .strip_prefix("temp_")
        .and_then(|r| r.strip_suffix("_degc"));
    if name == n && sensor.is_some_and(|s| !s.is_empty()) {
        return None;
    }
    let unit = n.rsplit_once('_').map(|(_, u)| u);
    let thermal = n.starts_with("temp") || unit.and_then(quantity) == Some(Quantity::Temperature);
    thermal.then(|| {
        format!(
            "column `{name}` looks like a thermometer: this reader reads one as `temp_<sensor>_degc` in °C (e.g. `temp_air_degc`)"
        )
    })
}

/// Why `name` looks like a measurement channel (`<channel>_<unit>` for one of `units`)
/// written in another unit of `quantities`, with its unit missing (`x`, `y1`) or spelt
/// another way (`X (µm)`); `None` when it does not.
pub(crate) fn channel_slip(name: &str, units: &[&str], quantities: &[Quantity]) -> Option<String> {
    let n = normalise(name);
    let expected = units
        .iter()
        .map(|u| format!("`<channel>_{u}`"))
        .collect::<Vec<_>>()
        .join(" or ");
    if let Some((stem, unit)) = n.rsplit_once('_')
        && !stem.is_empty()
    {
        if units.contains(&unit) && n != name {
            return Some(format!(
                "column `{name}`: this reader reads it as `{n}`; rename the column"
            ));
        }
        if !units.contains(&unit) && quantity(unit).is_some_and(|q| quantities.contains(&q)) {
            return Some(format!(
                "column `{name}` is in {unit}, but this reader reads channels as {expected}; convert the values and rename the column"
            ));
        }
    }
    // An axis letter, perhaps numbered: `x`, `y1`, `z2`, `a`.
    let bare = n.len() <= 3
        && n.starts_with(|c: char| "xyzabcuvw".contains(c))
        && n[1..].chars().all(|c| c.is_ascii_digit());
    bare.then(|| format!("column `{name}` has no unit: this reader reads channels as {expected}"))
}

/// A table's clock column: the one of the names a reader accepts that the header holds, and
/// its unit in seconds.
pub(crate) struct Clock {
    index: usize,
    name: &'static str,
    seconds: f64,
}

/// The clock column among `accepted` (name, seconds per unit), if the header has one; two
/// are refused (which would the figures follow?).
pub(crate) fn clock(
    header: &csv::StringRecord,
    accepted: &[(&'static str, f64)],
    line: u64,
    file: &str,
) -> Result<Option<Clock>, super::TableError> {
    let found: Vec<Clock> = accepted
        .iter()
        .filter_map(|&(name, seconds)| {
            let index = header.iter().position(|h| h == name)?;
            Some(Clock {
                index,
                name,
                seconds,
            })
        })
        .collect();
    match found.as_slice() {
        [_, second, ..] => Err(super::TableError::new(
            file,
            Some(line),
            format!(
                "columns `{}` and `{}`: two clocks; keep one",
                found[0].name, second.name
            ),
        )),
        _ => Ok(found.into_iter().next()),
    }
}

impl Clock {
    /// This row's time (s), within [`super::CLOCK_S`].
    pub(crate) fn seconds(
        &self,
        record: &csv::StringRecord,
        file: &str,
    ) -> Result<f64, super::TableError> {
        let range = super::Range {
            limit: super::CLOCK_S.limit / self.seconds,
            why: super::CLOCK_S.why,
        };
        Ok(super::number_within(record, self.index, self.name, file, range)? * self.seconds)
    }
}

/// The report's line for columns a reader read past (empty without any); a long list is cut
/// after ten names.
pub fn not_read_line<S: AsRef<str>>(columns: &[S]) -> String {
    if columns.is_empty() {
        return String::new();
    }
    let shown: Vec<&str> = columns.iter().take(10).map(AsRef::as_ref).collect();
    let more = match columns.len() {
        n if n > 10 => format!(" and {} more", n - 10),
        _ => String::new(),
    };
    format!(
        "Not read from the table (columns unknown to this reader; no figure depends on them): {}{more}.\n",
        shown.join(", ")
    )
}

/// Levenshtein distance between two short ASCII-ish names (by `char`).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut current = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            current[j + 1] = (previous[j] + usize::from(ca != *cb))
                .min(previous[j + 1] + 1)
                .min(current[j] + 1);
        }
        previous = current;
    }
    previous[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_normalised_as_the_readers_spell_theirs() {
        assert_eq!(normalise("Deviation (µm)"), "deviation_um");
        assert_eq!(normalise(" Target [mm] "), "target_mm");
        assert_eq!(normalise("temp_air_degc"), "temp_air_degc");
    }

    #[test]
    fn the_levenshtein_distance_of_hand_counted_pairs() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("deviaton_um", "deviation_um"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("time_min", "time_min"), 0);
    }

    #[test]
    fn a_column_like_a_known_one_is_refused_and_another_is_not() {
        let known = [
            "target_mm",
            "deviation_um",
            "axis",
            "run",
            "direction",
            "time_min",
        ];
        for slip in [
            "Deviation (µm)",
            "deviation_nm",
            "target_in",
            "deviation",
            "deviaton_um",
            "time_h",
        ] {
            assert!(looks_like(slip, &known).is_some(), "{slip}");
        }
        for other in [
            "status",
            "comment",
            "operator",
            "x_mm",
            "env_comp",
            "humidity_pct",
            "runs_total",
        ] {
            assert_eq!(looks_like(other, &known), None, "{other}");
        }
    }

    #[test]
    fn thermometers_and_channels_written_another_way() {
        assert_eq!(thermometer_slip("temp_air_degc"), None);
        for slip in [
            "temp_c",
            "temp_degc",
            "Temp_Air_degC",
            "spindle_degc",
            "air_c",
        ] {
            assert!(thermometer_slip(slip).is_some(), "{slip}");
        }
        assert_eq!(thermometer_slip("humidity_pct"), None);
        let lengths = [Quantity::Length, Quantity::Angle];
        for slip in ["x", "y1", "x_nm", "a_arcsec", "X (µm)"] {
            assert!(
                channel_slip(slip, &["um", "urad"], &lengths).is_some(),
                "{slip}"
            );
        }
        for other in [
            "x_um",
            "date",
            "pressure_hpa",
            "humidity_pct",
            "index",
            "id",
            "n",
        ] {
            assert_eq!(
                channel_slip(other, &["um", "urad"], &lengths),
                None,
                "{other}"
            );
        }
    }

    #[test]
    fn a_long_list_is_cut_after_ten_names() {
        let names: Vec<String> = (0..12).map(|i| format!("c{i}")).collect();
        let line = not_read_line(&names);
        assert!(line.contains("c9 and 2 more."), "{line}");
        assert!(!line.contains("c10"), "{line}");
        assert_eq!(not_read_line::<&str>(&[]), "");
    }
}
