//! What real exports carry beyond the figures: extra columns (read past and listed, the
//! figures unchanged), the clock in another unit, each capture on its own clock. Each test
//! rewrites a clean hand-built table as such an export would and checks the reading is the
//! same as the clean one's, number for number.

use super::plausible::{
    BALLBAR_PREAMBLE, ballbar_read, ballbar_rows, ballbar_text, positioning_rows,
};
use mtwin::kinds::positioning::PositioningTable;

/// The clean positioning rows as a table with `time` in `unit` (`min`, `s` or `h`) and
/// `extra` columns (name, cell) appended to every row.
fn laser_text(unit: &str, extra: &[(&str, &str)]) -> String {
    let scale = match unit {
        "min" => 1.0,
        "s" => 60.0,
        _ => 1.0 / 60.0,
    };
    let names: String = extra.iter().map(|(n, _)| format!(",{n}")).collect();
    let cells: String = extra.iter().map(|(_, c)| format!(",{c}")).collect();
    let mut text =
        format!("run,direction,target_mm,deviation_um,time_{unit},temp_air_degc{names}\n");
    for (run, direction, target, deviation, time, air) in positioning_rows() {
        text += &format!(
            "{run},{direction},{target:.3},{deviation:.4},{:.9},{air:.2}{cells}\n",
            time * scale
        );
    }
    text
}

#[test]
fn a_laser_export_with_extra_columns_and_its_clock_in_seconds_reads_as_the_clean_table() {
    let clean = PositioningTable::parse(laser_text("min", &[]).as_bytes(), "a.csv").unwrap();
    assert!(clean.columns_not_read.is_empty());
    let extra = [("status", "OK"), ("env_comp", "on"), ("comment", "")];
    for unit in ["s", "h"] {
        let export = PositioningTable::parse(laser_text(unit, &extra).as_bytes(), "b.csv").unwrap();
        assert_eq!(export.columns_not_read, ["status", "env_comp", "comment"]);
        assert_eq!(export.readings.len(), clean.readings.len());
        for (a, b) in clean.readings.iter().zip(&export.readings) {
            assert_eq!(
                (a.target, a.deviation, a.run),
                (b.target, b.deviation, b.run)
            );
            // The same instant to 1 ns (the cells carry 9 decimals of the unit).
            let (ta, tb) = (a.time.unwrap(), b.time.unwrap());
            assert!(
                (ta - tb).abs() < 1e-9 * 3600.0,
                "{unit}: {ta} s against {tb} s"
            );
        }
    }
}

#[test]
fn a_column_like_one_the_reader_reads_is_refused_by_name() {
    for (extra, words) in [
        ("Deviation (µm)", "this reader reads `deviation_um`"),
        (
            "deviation_nm",
            "is in nm, but this reader reads it as `deviation_um`",
        ),
        ("temp_c", "looks like a thermometer"),
        ("direction_", "this reader reads `direction`"),
        ("directon", "did you mean `direction`?"),
    ] {
        let text = laser_text("min", &[(extra, "1")]);
        let error = PositioningTable::parse(text.as_bytes(), "c.csv")
            .expect_err(extra)
            .to_string();
        assert!(
            error.starts_with("c.csv:1: ") && error.contains(words),
            "{extra}: {error}"
        );
    }
    let both = laser_text("min", &[("time_s", "1")]);
    let error = PositioningTable::parse(both.as_bytes(), "d.csv")
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("columns `time_min` and `time_s`: two clocks"),
        "{error}"
    );
}

#[test]
fn each_ball_bar_capture_on_its_own_clock_keeps_the_first_direction_of_the_file() {
    // The instrument saves each sense as its own run; joined, the cw capture's clock starts
    // at 0 again. The first direction is then the file's first, not the earliest time.
    let rows = ballbar_rows();
    let cw_start = rows.iter().find(|r| r.0 == "cw").unwrap().3;
    let restarted: Vec<_> = rows
        .iter()
        .map(|&(sense, angle, deviation, time)| {
            let time = if sense == "cw" { time - cw_start } else { time };
            (sense, angle, deviation, time)
        })
        .collect();
    let one_clock = ballbar_read(&ballbar_text(BALLBAR_PREAMBLE, &rows)).unwrap();
    let own_clocks = ballbar_read(&ballbar_text(BALLBAR_PREAMBLE, &restarted)).unwrap();
    assert_eq!(one_clock.readings.len(), own_clocks.readings.len());
    // On one clock a cw sweep listed first, but later in time, is still refused.
    let cw_first = BALLBAR_PREAMBLE.replace("first_direction = ccw", "first_direction = cw");
    let error = ballbar_read(&ballbar_text(&cw_first, &rows)).unwrap_err();
    assert!(
        error.contains("first_direction = cw") && error.contains("runs ccw"),
        "{error}"
    );
}
