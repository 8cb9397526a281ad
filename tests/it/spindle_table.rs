//! The `spindle` table (reader, writer, errors with file and line) against hand-written files
//! and a foreign export written by an independent script (`tests/data/spindle/make_foreign.py`),
//! and the spindle plots (SVG) against hand-computed coordinates.

use mtwin::kinds::spindle::plot::{PolarCurve, line_svg, polar_svg, spectrum_svg};
use mtwin::kinds::spindle::table::{SpindleTable, parse, read, write_csv};
use mtwin::kinds::spindle::{Sensing, SpindleRecord};
use mtwin::machine::Axis;
use mtwin::math::Real;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

const UM: Real = 1e-6;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/spindle")
        .join(name)
}

fn close(a: Real, b: Real, tolerance: Real) -> bool {
    (a - b).abs() <= tolerance
}

/// The error text of a table that must be refused.
fn refused(text: &str) -> String {
    match parse(text.as_bytes(), "t.csv") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

// ---------------------------------------------------------------------------------------------
// Reading the hand-written table.

#[test]
fn the_hand_written_table_reads_as_written() {
    let table = read(&data("small.csv")).unwrap();
    let r = &table.record;
    assert_eq!(r.axis, Axis::S);
    assert_eq!(table.samples_per_revolution, 8);
    assert_eq!(r.len(), 16);
    assert_eq!(
        r.revolution,
        [0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1]
    );
    assert!(r.setup.iter().all(String::is_empty));
    // Probes in column order, geometry from the preamble; y's direction 0 1.0000005 0
    // normalised.
    assert_eq!(r.probes.len(), 2);
    assert_eq!(r.probes[0].name, "x");
    assert_eq!(r.probes[0].direction, [1.0, 0.0, 0.0]);
    assert!(close(r.probes[0].position[0], -0.0127, 1e-15));
    assert_eq!(r.probes[0].sensing, Sensing::Fixed);
    assert_eq!(r.probes[1].name, "y");
    assert_eq!(r.probes[1].direction, [0.0, 1.0, 0.0]);
    assert!(close(r.probes[1].position[1], -0.0127, 1e-15));
    assert_eq!(r.probe("y"), Some(1));
    // Line 24: 1,45,0.05625,1200,1.464,1.384
    assert!(close(r.angle[9], PI / 4.0, 1e-15));
    assert!(close(r.time[9], 0.05625, 1e-15));
    assert!(close(r.speed[9], 40.0 * PI, 1e-12), "1200 rpm = 40π rad/s");
    assert!(close(r.readings[0][9], 1.464e-6, 1e-18));
    assert!(close(r.readings[1][9], 1.384e-6, 1e-18));
    // Line 22: 0,315,…,1.414,-1.414
    assert!(close(r.angle[7], 7.0 * PI / 4.0, 1e-15));
    assert!(close(r.readings[1][7], -1.414e-6, 1e-18));
    // The preamble is kept whole, with its lines.
    assert_eq!(
        table.conditions.get("artefact"),
        Some(("sphere 25.4 mm", 5))
    );
    assert_eq!(table.conditions.get("machine"), Some(("vmc3", 2)));
    assert_eq!(table.conditions.get("x_sensing"), Some(("fixed", 10)));
}

#[test]
fn the_writer_writes_this_text() {
    let table = read(&data("small.csv")).unwrap();
    let text = write_csv(&table);
    let expected_head = "# mtwin spindle table\n\
        # machine = vmc3\n\
        # artefact = sphere 25.4 mm\n\
        # bandwidth_hz = 10000\n\
        # resolution_nm = 1\n\
        # axis = S\n\
        # samples_per_revolution = 8\n\
        # x_direction = 1 0 0\n\
        # x_position_mm = -12.7 0 0\n\
        # x_sensing = fixed\n\
        # y_direction = 0 1 0\n\
        # y_position_mm = 0 -12.7 0\n\
        # y_sensing = fixed\n\
        revolution,angle_deg,time_s,speed_rpm,x_um,y_um\n\
        0,0.000000,0.000000,1200.000,2.000000,0.000000\n\
        0,45.000000,0.006250,1200.000,1.414000,1.414000\n";
    assert!(text.starts_with(expected_head), "{text}");
    assert!(
        text.ends_with("\n1,315.000000,0.093750,1200.000,1.464000,-1.444000\n"),
        "{text}"
    );
    assert_eq!(text.lines().count(), 14 + 16);
}

/// Write → read gives the record back (readings to the writer's 1 pm), and writing what was
/// read gives the same bytes.
fn assert_round_trip(table: &SpindleTable) {
    let text = write_csv(table);
    let back = parse(text.as_bytes(), "written.csv").unwrap();
    let (a, b) = (&table.record, &back.record);
    assert_eq!(back.samples_per_revolution, table.samples_per_revolution);
    assert_eq!(a.axis, b.axis);
    assert_eq!(a.setup, b.setup);
    assert_eq!(a.revolution, b.revolution);
    assert_eq!(a.probes.len(), b.probes.len());
    for (p, q) in a.probes.iter().zip(&b.probes) {
        assert_eq!(p.name, q.name);
        assert_eq!(p.sensing, q.sensing);
        for j in 0..3 {
            assert!(close(p.direction[j], q.direction[j], 1e-9), "{p:?} {q:?}");
            assert!(close(p.position[j], q.position[j], 1e-12), "{p:?} {q:?}");
        }
    }
    for i in 0..a.len() {
        assert!(close(a.angle[i], b.angle[i], 1e-8), "sample {i}");
        assert!(close(a.time[i], b.time[i], 5e-7), "sample {i}");
        assert!(close(a.speed[i], b.speed[i], 1e-4), "sample {i}");
        for p in 0..a.probes.len() {
            assert!(
                close(a.readings[p][i], b.readings[p][i], 5e-13),
                "sample {i}"
            );
        }
    }
    for key in table.conditions.keys() {
        if !key.ends_with("_direction") {
            assert_eq!(
                table.conditions.get(key).map(|v| v.0),
                back.conditions.get(key).map(|v| v.0),
                "{key}"
            );
        }
    }
    assert_eq!(write_csv(&back), text, "write(read(write(t))) = write(t)");
}

#[test]
fn write_then_read_round_trips() {
    assert_round_trip(&read(&data("small.csv")).unwrap());
    assert_round_trip(&read(&data("foreign_sea.csv")).unwrap());
}

// ---------------------------------------------------------------------------------------------
// The foreign export.

#[test]
fn a_foreign_export_reads_with_conventional_geometry() {
    let table = read(&data("foreign_sea.csv")).unwrap();
    let r = &table.record;
    assert_eq!(table.samples_per_revolution, 32, "inferred");
    assert_eq!(r.axis, Axis::S, "default");
    assert_eq!(r.len(), 128);
    // Revolutions 1…4 in the file, stored from 0.
    assert_eq!(r.revolution[0], 0);
    assert_eq!(r.revolution[32], 1);
    assert_eq!(r.revolution[127], 3);
    let names: Vec<&str> = r.probes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["z", "y2", "x2", "y1", "x1"]);
    let probe = |name: &str| &r.probes[r.probe(name).unwrap()];
    assert_eq!(probe("x1").direction, [1.0, 0.0, 0.0]);
    assert_eq!(probe("x1").position, [0.0, 0.0, 0.0]);
    assert_eq!(probe("y1").direction, [0.0, 1.0, 0.0]);
    assert_eq!(probe("x2").direction, [1.0, 0.0, 0.0]);
    assert!(
        close(probe("x2").position[2], 0.060, 1e-15),
        "station 60 mm up"
    );
    assert_eq!(probe("y2").direction, [0.0, 1.0, 0.0]);
    assert!(close(probe("y2").position[2], 0.060, 1e-15));
    assert_eq!(probe("z").direction, [0.0, 0.0, 1.0]);
    assert!(r.probes.iter().all(|p| p.sensing == Sensing::Fixed));
    // No speed column: 3000 rpm (100π rad/s) from the times, in every sample.
    assert!(
        r.speed.iter().all(|w| close(*w, 100.0 * PI, 1e-9)),
        "{}",
        r.speed[0]
    );
    // Line 40: 0.020000,0.108,0.000,2.228,4.157,2,1.494,3.804 (revolution 2's first sample).
    let i = 32;
    assert!(close(r.time[i], 0.02, 1e-15));
    assert_eq!(r.angle[i], 0.0);
    let reading = |name: &str| r.readings[r.probe(name).unwrap()][i];
    assert!(close(reading("z"), 0.108 * UM, 1e-18));
    assert!(close(reading("y2"), 2.228 * UM, 1e-18));
    assert!(close(reading("x2"), 4.157 * UM, 1e-18));
    assert!(close(reading("y1"), 1.494 * UM, 1e-18));
    assert!(close(reading("x1"), 3.804 * UM, 1e-18));
    // Line 135, the last: 0.079375,0.131,348.750,…
    assert!(close(r.angle[127], 348.75 * PI / 180.0, 1e-15));
    assert!(close(r.time[127], 0.079375, 1e-15));
    assert_eq!(table.conditions.get("bandwidth_hz"), Some(("15000", 6)));
    assert_eq!(
        table.conditions.get("station_separation_mm"),
        Some(("60", 5))
    );
}

/// A radial probe given by its angle alone faces the axis from that azimuth: direction
/// `−(cos φ, sin φ, 0)`, at `NAME_height_mm`; the angle and a direction together are refused
/// at the angle's line.
#[test]
fn a_probe_given_by_its_azimuth_faces_the_axis_from_there() {
    let rows = "revolution,angle_deg,speed_rpm,p1_um,p2_um,p3_um\n0,0,60,0,0,0\n0,120,60,0,0,0\n0,240,60,0,0,0\n";
    let text = format!(
        "# p1_azimuth_deg = 30\n# p2_azimuth_deg = 150\n# p2_height_mm = 12.5\n# p3_azimuth_deg = -90\n{rows}"
    );
    let table = parse(text.as_bytes(), "t.csv").unwrap();
    let r = &table.record;
    let probe = |name: &str| &r.probes[r.probe(name).unwrap()];
    let s3 = 3f64.sqrt() / 2.0;
    for (name, want) in [("p1", [-s3, -0.5]), ("p2", [s3, -0.5]), ("p3", [0.0, 1.0])] {
        let d = probe(name).direction;
        assert!(
            close(d[0], want[0], 1e-15) && close(d[1], want[1], 1e-15) && d[2] == 0.0,
            "{name}: {d:?}"
        );
        assert_eq!(probe(name).sensing, Sensing::Fixed);
    }
    assert!(close(probe("p2").position[2], 0.0125, 1e-15));
    assert_eq!(probe("p1").position, [0.0, 0.0, 0.0]);
    assert!(table.conditions.unread().is_empty(), "every key read");

    let both = format!(
        "# p1_azimuth_deg = 30\n# p1_direction = 1 0 0\n# p2_azimuth_deg = 0\n# p3_azimuth_deg = 90\n{rows}"
    );
    let error = refused(&both);
    assert!(
        error.contains("t.csv:1:") && error.contains("either `p1_azimuth_deg`"),
        "{error}"
    );
    let nan =
        format!("# p1_azimuth_deg = north\n# p2_azimuth_deg = 0\n# p3_azimuth_deg = 90\n{rows}");
    let error = refused(&nan);
    assert!(
        error.contains("t.csv:1:") && error.contains("expected a finite number"),
        "{error}"
    );
}

#[test]
fn errors_in_a_crlf_export_name_the_right_line() {
    let text = std::fs::read_to_string(data("foreign_sea.csv")).unwrap();
    assert!(text.contains("\r\n"));
    let bad = text.replacen(
        "0.020625,0.060,11.250,3.005,3.625,2,2.273,3.479",
        "0.020625,0.060,11.250,3.005,3.6x5,2,2.273,3.479",
        1,
    );
    let error = parse(bad.as_bytes(), "sea.csv").unwrap_err();
    assert_eq!(
        error.to_string(),
        "sea.csv:41: column `x2_um`: expected a finite number, found \"3.6x5\""
    );
    // Without the station separation, x2 and y2 have no height.
    let bad = text.replace("# station_separation_mm = 60\r\n", "");
    let error = parse(bad.as_bytes(), "sea.csv").unwrap_err();
    assert_eq!(
        error.to_string(),
        "sea.csv:6: column `y2_um`: probe `y2` needs `station_separation_mm` in the preamble \
         (or `y2_direction` and `y2_position_mm`)"
    );
}

// ---------------------------------------------------------------------------------------------
// The malformed fixtures.

fn fixture_error(name: &str) -> (String, Option<u64>) {
    let path = data(name);
    let error = read(&path).unwrap_err();
    let prefix = format!("{}:", path.display());
    let text = error.to_string();
    let text = text.strip_prefix(&prefix).unwrap_or(&text).to_string();
    (text, error.line())
}

#[test]
fn a_table_without_probe_columns_is_refused_at_its_header() {
    let (text, line) = fixture_error("missing_probes.csv");
    assert_eq!(line, Some(8));
    assert_eq!(
        text,
        "8: no probe column: give one `NAME_um` column per probe (e.g. `x_um`, `y_um`)"
    );
}

#[test]
fn a_short_revolution_is_refused_where_it_ends() {
    let (text, line) = fixture_error("short_revolution.csv");
    assert_eq!(line, Some(29));
    assert_eq!(
        text,
        "29: revolution 1 ends here after 7 samples; every revolution has 8 \
         (samples_per_revolution in the preamble)"
    );
}

#[test]
fn an_angle_that_does_not_increase_is_refused() {
    let (text, line) = fixture_error("angle_not_increasing.csv");
    assert_eq!(line, Some(18));
    assert_eq!(
        text,
        "18: column `angle_deg`: 90 does not increase from 135 on the row before \
         (angles increase strictly within a revolution)"
    );
}

#[test]
fn a_nan_reading_is_refused() {
    let (text, line) = fixture_error("nan.csv");
    assert_eq!(line, Some(20));
    assert_eq!(
        text,
        "20: column `y_um`: expected a finite number, found \"NaN\""
    );
}

#[test]
fn a_missing_file_is_named() {
    let path = data("no_such_table.csv");
    let error = read(&path).unwrap_err().to_string();
    assert!(
        error.starts_with(&format!("{}: cannot read:", path.display())),
        "{error}"
    );
}

// ---------------------------------------------------------------------------------------------
// Checks, one by one, on small tables in memory.

#[test]
fn revolutions_must_have_equal_length_and_follow_each_other() {
    // A long revolution (5 samples where the first had 4), inferred length.
    let text = "x_um,revolution,angle_deg,time_s\n0,0,0,0\n0,0,90,0.5\n0,0,180,1\n0,0,270,1.5\n\
                0,1,0,2\n0,1,90,2.5\n0,1,180,3\n0,1,270,3.5\n0,1,300,4\n";
    assert_eq!(
        refused(text),
        "t.csv:10: revolution 1 ends here after 5 samples; every revolution has 4 \
         (samples_per_revolution inferred from the first revolution)"
    );
    // A revolution skipped.
    let text = "x_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n0,0,180,60\n0,2,0,60\n0,2,180,60\n";
    assert_eq!(
        refused(text),
        "t.csv:4: column `revolution`: revolution 2 follows revolution 0 (revolutions are consecutive)"
    );
    // A declared length the revolutions do not have.
    let text =
        "# samples_per_revolution = 3\nx_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n0,0,180,60\n";
    assert_eq!(
        refused(text),
        "t.csv:4: revolution 0 ends here after 2 samples; every revolution has 3 \
         (samples_per_revolution in the preamble)"
    );
    // Not a revolution number.
    let text = "x_um,revolution,angle_deg,speed_rpm\n0,1.5,0,60\n";
    assert_eq!(
        refused(text),
        "t.csv:2: column `revolution`: expected a revolution number (0, 1, …), found \"1.5\""
    );
}

#[test]
fn angles_must_lie_in_a_turn() {
    let text = "x_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n0,0,360,60\n";
    assert_eq!(
        refused(text),
        "t.csv:3: column `angle_deg`: 360 is outside [0, 360)"
    );
    let text = "x_um,revolution,angle_deg,speed_rpm\n0,0,-1,60\n";
    assert_eq!(
        refused(text),
        "t.csv:2: column `angle_deg`: -1 is outside [0, 360)"
    );
}

#[test]
fn the_header_needs_its_columns() {
    assert_eq!(
        refused("x_um,angle_deg,speed_rpm\n0,0,60\n"),
        "t.csv:1: missing column `revolution` (required: revolution, angle_deg, time_s or speed_rpm, and NAME_um per probe)"
    );
    assert_eq!(
        refused("# a = 1\nx_um,revolution,angle_deg\n0,0,0\n"),
        "t.csv:2: missing column `time_s` or `speed_rpm` (at least one is required)"
    );
    assert_eq!(
        refused("x_um,revolution,angle_deg,speed_rpm,y_mm\n0,0,0,60,20\n"),
        "t.csv:1: column `y_mm` is in mm, but this reader reads channels as `<channel>_um`; \
         convert the values and rename the column (this reader reads setup, revolution, \
         angle_deg, time_s, speed_rpm and one NAME_um per probe)"
    );
    assert_eq!(
        refused("X1_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n"),
        "t.csv:1: column `X1_um`: a probe's name is lower-case letters, digits and `_` \
         (its preamble keys are `NAME_direction`, `NAME_position_mm`, `NAME_sensing`)"
    );
    assert_eq!(
        refused("x_um,revolution,angle_deg,speed_rpm\n"),
        "t.csv: no data rows"
    );
}

#[test]
fn probe_geometry_comes_from_keys_or_conventional_names() {
    // An unconventional name without keys.
    assert_eq!(
        refused("cap3_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n"),
        "t.csv:1: column `cap3_um`: no geometry for probe `cap3`: give `cap3_direction = dx dy dz` \
         and `cap3_position_mm = x y z`, or `cap3_azimuth_deg` for a radial probe, in the \
         preamble (names with defaults: x, x1, y, y1, x2, \
         y2, z, face)"
    );
    // A direction that is not a unit vector.
    let text = "# x_direction = 1 1 0\nx_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n";
    assert_eq!(
        refused(text),
        "t.csv:1: x_direction = 1 1 0: not a unit vector (length 1.414213562); give it to within 1e-6"
    );
    // A position that is not three numbers.
    let text = "# cap_direction = 0 0 -1\n# cap_position_mm = 1 2\ncap_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n";
    assert_eq!(
        refused(text),
        "t.csv:2: cap_position_mm = 1 2: expected three numbers separated by spaces"
    );
    // An unknown sensing.
    let text = "# x_sensing = spinning\nx_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n";
    assert_eq!(
        refused(text),
        "t.csv:1: x_sensing = spinning: expected fixed or rotating"
    );
    // The face probe needs its radius; given, it sits there looking along +z.
    assert_eq!(
        refused("face_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n"),
        "t.csv:1: column `face_um`: probe `face` needs `face_radius_mm` in the preamble (or \
         `face_direction` and `face_position_mm`)"
    );
    let text =
        "# face_radius_mm = 40\n# axis = c\nface_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n";
    let table = parse(text.as_bytes(), "t.csv").unwrap();
    assert_eq!(table.record.axis, Axis::C);
    let face = &table.record.probes[0];
    assert_eq!(face.direction, [0.0, 0.0, 1.0]);
    assert!(close(face.position[0], 0.040, 1e-15));
    assert_eq!((face.position[1], face.position[2]), (0.0, 0.0));
    // Keys win over the conventional name, and a rotating probe with its own keys.
    let text = "# x_direction = -0.6 0.8 0\n# x_position_mm = 10 0 5\n# x_sensing = rotating\n\
                # cap_direction = 0 0 -1\n# cap_position_mm = 0 0 30\n\
                x_um,cap_um,revolution,angle_deg,speed_rpm\n0,0,0,0,60\n";
    let table = parse(text.as_bytes(), "t.csv").unwrap();
    let x = &table.record.probes[0];
    assert_eq!(x.sensing, Sensing::Rotating);
    assert!(close(x.direction[0], -0.6, 1e-15) && close(x.direction[1], 0.8, 1e-15));
    assert!(close(x.position[0], 0.010, 1e-15) && close(x.position[2], 0.005, 1e-15));
    let cap = &table.record.probes[1];
    assert_eq!(cap.direction, [0.0, 0.0, -1.0]);
    assert!(close(cap.position[2], 0.030, 1e-15));
}

#[test]
fn preamble_values_are_checked() {
    assert_eq!(
        refused("# axis = X\nx_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n"),
        "t.csv:1: axis = X: expected S, C, A or B (the axis of rotation)"
    );
    assert_eq!(
        refused("# samples_per_revolution = 0\nx_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n"),
        "t.csv:1: samples_per_revolution = 0: expected a positive whole number"
    );
    assert_eq!(
        refused("# bandwidth_hz = fast\nx_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n"),
        "t.csv:1: bandwidth_hz = fast: expected a finite number"
    );
}

// ---------------------------------------------------------------------------------------------
// Time and speed, one from the other; runs.

#[test]
fn time_follows_from_the_speed() {
    // 600 rpm = 10 rev/s: 90° takes 0.025 s.
    let mut text = String::from("x_um,revolution,angle_deg,speed_rpm\n");
    for i in 0..8 {
        text += &format!("0,{},{},600\n", i / 4, 90 * (i % 4));
    }
    let table = parse(text.as_bytes(), "t.csv").unwrap();
    let expected = [0.0, 0.025, 0.05, 0.075, 0.1, 0.125, 0.15, 0.175];
    for (t, e) in table.record.time.iter().zip(expected) {
        assert!(close(*t, e, 1e-12), "{:?}", table.record.time);
    }
    assert!(
        table
            .record
            .speed
            .iter()
            .all(|w| close(*w, 20.0 * PI, 1e-12))
    );
}

#[test]
fn speed_follows_from_the_time() {
    // 90° every 0.5 s: a quarter revolution per 0.5 s = 30 rpm = π rad/s.
    let mut text = String::from("x_um,revolution,angle_deg,time_s\n");
    for i in 0..8 {
        text += &format!("0,{},{},{}\n", i / 4, 90 * (i % 4), 0.5 * i as Real);
    }
    let table = parse(text.as_bytes(), "t.csv").unwrap();
    assert!(
        table.record.speed.iter().all(|w| close(*w, PI, 1e-12)),
        "{:?}",
        table.record.speed
    );
    // Times that do not move give speed 0.
    let text = "x_um,revolution,angle_deg,time_s\n0,0,0,1\n0,0,180,1\n";
    let table = parse(text.as_bytes(), "t.csv").unwrap();
    assert_eq!(table.record.speed, [0.0, 0.0]);
}

#[test]
fn a_static_record_counts_time_in_revolutions() {
    let text = "x_um,revolution,angle_deg,speed_rpm\n0,0,0,0\n0,0,180,0\n0,1,0,0\n0,1,180,0\n";
    let table = parse(text.as_bytes(), "t.csv").unwrap();
    assert_eq!(table.record.time, [0.0, 0.5, 1.0, 1.5]);
    assert_eq!(table.record.speed, [0.0; 4]);
}

#[test]
fn runs_split_on_setup_speed_and_a_revolution_restart() {
    // Set-up a at 60 rpm (2 revolutions), set-up a at -120 rpm (revolutions 5, 6: stored 0, 1),
    // set-up "b, reversed" at -120 rpm (revolutions 0 and 1, the second at other angles; at a
    // negative speed the angle runs down from the index: 0, 180 then 270, 90), then a restart
    // to revolution 0 at the same set-up and speed.
    let text = "setup,revolution,angle_deg,speed_rpm,x_um\n\
                a,0,0,60,1\na,0,180,60,2\na,1,0,60,3\na,1,180,60,4\n\
                a,5,0,-120,5\na,5,180,-120,6\na,6,0,-120,7\na,6,180,-120,8\n\
                \"b, reversed\",0,0,-120,9\n\"b, reversed\",0,180,-120,10\n\
                \"b, reversed\",1,270,-120,11\n\"b, reversed\",1,90,-120,12\n\
                \"b, reversed\",0,0,-120,13\n\"b, reversed\",0,180,-120,14\n";
    let table = parse(text.as_bytes(), "t.csv").unwrap();
    let r = &table.record;
    assert_eq!(table.samples_per_revolution, 2);
    assert_eq!(r.revolution, [0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0][..]);
    assert_eq!(r.setup[8], "b, reversed");
    assert!(close(r.speed[4], -4.0 * PI, 1e-12));
    assert!(close(r.readings[0][13], 14.0 * UM, 1e-18));
    // Times: 60 rpm → 180° in 0.5 s; 120 rpm (720°/s) → 180° in 0.25 s, 270° in 0.375 s, and
    // one sample period (0.25 s at 120 rpm, 2 samples per revolution) from one run to the next.
    let expected = [
        0.0, 0.5, 1.0, 1.5, 1.75, 2.0, 2.25, 2.5, 2.75, 3.0, 3.375, 3.625, 3.875, 4.125,
    ];
    assert_eq!(r.time.len(), expected.len());
    for (t, e) in r.time.iter().zip(expected) {
        assert!(close(*t, e, 1e-12), "{:?}", r.time);
    }
    // Quoted set-up names survive the writer.
    assert!(
        write_csv(&table).contains("\n\"b, reversed\",0,0.000000,2.750000,-120.000,9.000000\n")
    );
    assert_round_trip(&table);
    // A restart with the same revolution number continues the revolution: refused as angles.
    let text = "x_um,revolution,angle_deg,speed_rpm\n0,0,0,60\n0,0,180,60\n0,0,0,60\n0,0,180,60\n";
    assert_eq!(
        refused(text),
        "t.csv:4: column `angle_deg`: 0 does not increase from 180 on the row before \
         (angles increase strictly within a revolution)"
    );
}

#[test]
fn the_writer_keeps_angles_below_a_turn() {
    let table = SpindleTable {
        record: SpindleRecord {
            axis: Axis::B,
            probes: read(&data("small.csv")).unwrap().record.probes,
            setup: vec![String::new(); 2],
            revolution: vec![0, 0],
            angle: vec![0.0, 2.0 * PI - 1e-12],
            time: vec![0.0, 1.0],
            speed: vec![0.0, 0.0],
            readings: vec![vec![-1e-15, 1e-6], vec![0.0, 0.0]],
        },
        conditions: Default::default(),
        samples_per_revolution: 2,
        columns_not_read: Vec::new(),
    };
    let text = write_csv(&table);
    assert!(
        text.contains("\n0,0.000000,0.000000,0.000,0.000000,0.000000\n"),
        "{text}"
    );
    assert!(
        text.contains("\n0,359.999999,1.000000,0.000,1.000000,0.000000\n"),
        "{text}"
    );
    assert!(text.contains("# axis = B\n"));
    assert_eq!(
        parse(text.as_bytes(), "t.csv").unwrap().record.axis,
        Axis::B
    );
}

// ---------------------------------------------------------------------------------------------
// Plots.

/// The elements named `name` in `svg`, each with its attributes; panics unless `svg` is
/// well-formed XML with one `<svg>` root.
fn elements(svg: &str, name: &str) -> Vec<Vec<(String, String)>> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(svg);
    let mut out = Vec::new();
    let (mut depth, mut roots) = (0usize, 0usize);
    loop {
        let event = reader.read_event().expect("well-formed XML");
        let element = match &event {
            Event::Start(e) | Event::Empty(e) => e.clone(),
            Event::End(_) => {
                depth -= 1;
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        if depth == 0 {
            roots += 1;
            assert_eq!(element.name().as_ref(), b"svg");
        }
        if matches!(event, Event::Start(_)) {
            depth += 1;
        }
        if element.name().as_ref() == name.as_bytes() {
            out.push(
                element
                    .attributes()
                    .map(|a| {
                        let a = a.expect("attribute");
                        (
                            String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                            String::from_utf8_lossy(&a.value).into_owned(),
                        )
                    })
                    .collect(),
            );
        }
    }
    assert_eq!((depth, roots), (0, 1), "one root, closed");
    out
}

fn attribute<'a>(element: &'a [(String, String)], key: &str) -> &'a str {
    element
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
        .unwrap_or_else(|| panic!("no `{key}` in {element:?}"))
}

const QUARTERS: [Real; 4] = [0.0, PI / 2.0, PI, 1.5 * PI];

#[test]
fn a_polar_plot_draws_points_where_computed_by_hand() {
    // Residuals 0, 1, 2, 1 µm at 0°, 90°, 180°, 270°; band [0, 2] µm (rings every 0.5 µm)
    // drawn from 160 to 240 px about (300, 310): R = 160 + 40·ρ.
    let values = [0.0, 1.0 * UM, 2.0 * UM, 1.0 * UM];
    let curve = PolarCurve {
        label: "synchronous <S> & co",
        angles: &QUARTERS,
        values: &values,
        stroke: "#000",
        width: 1.5,
    };
    let notes = ["synchronous value (PC): 2.000 µm".to_string()];
    let svg = polar_svg("Radial <X>", &[curve], [0.0, 0.0], (0.0, 2.0 * UM), &notes);
    let lines = elements(&svg, "polyline");
    assert_eq!(lines.len(), 1, "{svg}");
    // One revolution round the circle: closed back to its first point.
    let expected = "460.0,310.0 300.0,110.0 60.0,310.0 300.0,510.0 460.0,310.0";
    assert_eq!(attribute(&lines[0], "points"), expected);
    assert_eq!(attribute(&lines[0], "stroke"), "#000");
    // The same circle seen from a centre 1 µm along +x: a constant 1 µm becomes
    // 1 − cos θ = 0, 1, 2, 1 — the same drawing (the limaçon sense).
    let shifted = [1.0 * UM; 4];
    let curve = PolarCurve {
        values: &shifted,
        ..curve
    };
    let svg_shifted = polar_svg(
        "Radial <X>",
        &[curve],
        [1.0 * UM, 0.0],
        (0.0, 2.0 * UM),
        &notes,
    );
    let lines = elements(&svg_shifted, "polyline");
    assert_eq!(attribute(&lines[0], "points"), expected);
    // The two dashed circles of the value at 160 and 240 px, and the rings 0…2 µm.
    let circles = elements(&svg, "circle");
    let dashed: Vec<&str> = circles
        .iter()
        .filter(|c| c.iter().any(|(k, _)| k == "stroke-dasharray"))
        .map(|c| attribute(c, "r"))
        .collect();
    assert_eq!(dashed, ["160.0", "240.0"]);
    assert_eq!(circles.len(), 2 + 5, "two bounds and five rings");
    assert!(svg.contains(">synchronous value (PC): 2.000 µm</text>"));
    assert!(svg.contains("synchronous &lt;S&gt; &amp; co"));
    assert!(
        svg.contains(">centre: x 0.000 µm, y 0.000 µm</text>"),
        "{svg}"
    );
    assert!(
        svg_shifted.contains(">centre: x 1.000 µm, y 0.000 µm</text>"),
        "{svg_shifted}"
    );
}

#[test]
fn a_total_plot_is_one_polyline_per_revolution() {
    // Three revolutions of 8 angles, and their average: 3 + 1 polylines.
    let angles: Vec<Real> = (0..24).map(|i| (i % 8) as Real * PI / 4.0).collect();
    let total: Vec<Real> = (0..24)
        .map(|i| (0.2 * (i / 8) as Real + (i % 3) as Real * 0.1) * UM)
        .collect();
    let synchronous: Vec<Real> = (0..8).map(|m| 0.3 * UM + 0.1 * m as Real * UM).collect();
    let curves = [
        PolarCurve {
            label: "total",
            angles: &angles,
            values: &total,
            stroke: "#bbb",
            width: 0.8,
        },
        PolarCurve {
            label: "synchronous",
            angles: &angles[..8],
            values: &synchronous,
            stroke: "#1f77b4",
            width: 1.5,
        },
    ];
    let svg = polar_svg("Total", &curves, [0.0, 0.0], (0.3 * UM, 1.0 * UM), &[]);
    let lines = elements(&svg, "polyline");
    assert_eq!(lines.len(), 4);
    let count = |l: &Vec<(String, String)>| attribute(l, "points").split(' ').count();
    // Each revolution joined to the next one's first point; the last left open; the
    // synchronous curve closed.
    assert_eq!(lines.iter().map(count).collect::<Vec<_>>(), [9, 9, 8, 9]);
    // Band [0, 1] µm (the total's least, the synchronous's greatest): R = 160 + 80·ρ; rings
    // every 0.2 µm; the dashed circles at 0.3 and 1.0 µm.
    let circles = elements(&svg, "circle");
    let dashed: Vec<&str> = circles
        .iter()
        .filter(|c| c.iter().any(|(k, _)| k == "stroke-dasharray"))
        .map(|c| attribute(c, "r"))
        .collect();
    assert_eq!(dashed, ["184.0", "240.0"]);
    assert_eq!(
        circles.len(),
        2 + 6,
        "two bounds and rings at 0, 0.2, …, 1 µm"
    );
    assert!(svg.contains(">rings every 0.2 µm</text>"));
    // A partial arc (a swivel of 90°) is not closed.
    let arc = [0.0, PI / 6.0, PI / 3.0, PI / 2.0];
    let curve = PolarCurve {
        label: "arc",
        angles: &arc,
        values: &[0.0; 4],
        stroke: "red",
        width: 1.0,
    };
    let svg = polar_svg("Arc", &[curve], [0.0, 0.0], (0.0, 0.0), &[]);
    let lines = elements(&svg, "polyline");
    assert_eq!(lines.len(), 1);
    assert_eq!(count(&lines[0]), 4);
}

mod plots_and_speeds;
