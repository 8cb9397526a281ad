//! Plausible-but-wrong tables: each test builds a clean table by hand (its numbers chosen
//! here, a seeded noise on them), checks that it passes without a caution, then makes one slip
//! a real export or a tired user makes (a unit, a label, a copy, a cut) and checks that the
//! data's own evidence names it: a refusal from the reader, or a caution naming the column.

use mtwin::kinds::ballbar::iso230_4::CircularTest;
use mtwin::kinds::ballbar::plausible as ballbar_plausible;
use mtwin::kinds::ballbar::table::BallbarTable;
use mtwin::kinds::drift::plausible as drift_plausible;
use mtwin::kinds::drift::table::DriftTable;
use mtwin::kinds::positioning::plausible as positioning_plausible;
use mtwin::kinds::positioning::table::PositioningTable;
use mtwin::kinds::probe::analysis::evaluate as evaluate_probe;
use mtwin::kinds::probe::table::ProbeTable;
use mtwin::machine::Plane;

/// A deterministic noise in [−1, 1) (a 64-bit LCG), so the tables are the same every run.
pub(super) struct Noise(pub(super) u64);

impl Noise {
    pub(super) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Rows of an ISO 230-2 linear cycle on X (5 runs, targets 0, 50 … 500 mm, up then down):
/// deviation = 12 µm/m of scale + 1.5 µm of lost motion against the travel + 0.1 µm noise,
/// a reading every 6 s. Each row: run, direction, target_mm, deviation_um, time_min, air °C.
pub(super) fn positioning_rows() -> Vec<(String, &'static str, f64, f64, f64, f64)> {
    let mut noise = Noise(7);
    let mut rows = Vec::new();
    let mut t = 0.0;
    for run in 1..=5 {
        for (direction, targets) in [
            ("+", (0..=10).collect::<Vec<_>>()),
            ("-", (0..=10).rev().collect::<Vec<_>>()),
        ] {
            for k in targets {
                let target = 50.0 * k as f64;
                let lost = if direction == "+" { -0.75 } else { 0.75 };
                let deviation = 0.012 * target + lost + 0.1 * noise.next();
                t += 0.1;
                rows.push((run.to_string(), direction, target, deviation, t, 20.2));
            }
        }
    }
    rows
}

pub(super) fn positioning_text(rows: &[(String, &str, f64, f64, f64, f64)]) -> String {
    let mut text = String::from("run,direction,target_mm,deviation_um,time_min,temp_air_degc\n");
    for (run, direction, target, deviation, time, air) in rows {
        text += &format!("{run},{direction},{target:.3},{deviation:.4},{time:.4},{air:.2}\n");
    }
    text
}

pub(super) fn positioning_cautions(rows: &[(String, &str, f64, f64, f64, f64)]) -> Vec<String> {
    let table = PositioningTable::parse(positioning_text(rows).as_bytes(), "laser.csv")
        .expect("the table reads");
    positioning_plausible::cautions(&table)
}

/// The one caution of `cautions`, which must contain each of `expected`.
pub(super) fn the_caution(cautions: &[String], expected: &[&str]) {
    assert_eq!(cautions.len(), 1, "one caution: {cautions:#?}");
    for e in expected {
        assert!(cautions[0].contains(e), "should name {e}: {}", cautions[0]);
    }
}

#[test]
fn positioning_slips_are_named_and_the_clean_table_is_not() {
    let clean = positioning_rows();
    assert_eq!(positioning_cautions(&clean), Vec::<String>::new());

    // Millimetres in the µm column: the 0.1 µm noise becomes 0.1 nm, a scatter at a target
    // (s ≈ 0.1 nm·0.58) no laser repeats to.
    let mm: Vec<_> = clean
        .iter()
        .map(|r| (r.0.clone(), r.1, r.2, r.3 / 1000.0, r.4, r.5))
        .collect();
    the_caution(
        &positioning_cautions(&mm),
        &["`deviation_um`", "mm in the µm column"],
    );

    // Nanometres in it: the 6 µm of scale reads 7.5 mm, beyond the 1 mm of any axis.
    let nm: Vec<_> = clean
        .iter()
        .map(|r| (r.0.clone(), r.1, r.2, r.3 * 1000.0, r.4, r.5))
        .collect();
    the_caution(
        &positioning_cautions(&nm),
        &["`deviation_um`", "nm in the µm column"],
    );

    // Run 3 alone in mm: it spans a thousandth of the others.
    let one_run: Vec<_> = clean
        .iter()
        .map(|r| {
            let d = if r.0 == "3" { r.3 / 1000.0 } else { r.3 };
            (r.0.clone(), r.1, r.2, d, r.4, r.5)
        })
        .collect();
    // (The stability check sees run 3 off the others too, and so does the reversal check:
    // run 3 reverses by a thousandth of 1.5 µm. Each says so; the unit is named.)
    let cautions = positioning_cautions(&one_run);
    assert_eq!(cautions.len(), 3, "{cautions:#?}");
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("`deviation_um`: run \"3\" spans")
                && c.contains("times less")
                && c.contains("another unit")),
        "{cautions:#?}"
    );

    // Runs 4 and 5 from another day, whose lost motion is 3 µm instead of 1.5: their
    // reversal (+ less −) is −3 µm against −1.5, where the noise (0.1/√3 µm a reading, so
    // about 0.08 µm on a difference, 11 targets) lets runs differ by about 8·0.08/√11 ≈ 0.2 µm.
    let mixed: Vec<_> = clean
        .iter()
        .map(|r| {
            let extra = match (r.0.as_str(), r.1) {
                ("4" | "5", "+") => -0.75,
                ("4" | "5", _) => 0.75,
                _ => 0.0,
            };
            (r.0.clone(), r.1, r.2, r.3 + extra, r.4, r.5)
        })
        .collect();
    let cautions = positioning_cautions(&mixed);
    assert!(
        cautions.iter().any(
            |c| c.contains("the reversal changes from run to run, from -3")
                && c.contains("runs of different conditions mixed")
        ),
        "{cautions:#?}"
    );

    // An export rounded to whole µm: the rounding is named (not a copy, not mm).
    let rounded: Vec<_> = clean
        .iter()
        .map(|r| (r.0.clone(), r.1, r.2, r.3.round(), r.4, r.5))
        .collect();
    the_caution(
        &positioning_cautions(&rounded),
        &["`deviation_um`: every reading is a whole multiple of 1 µm"],
    );

    // The direction labels swapped: every `+` reading was taken with the targets falling.
    let swapped: Vec<_> = clean
        .iter()
        .map(|r| {
            let d = if r.1 == "+" { "-" } else { "+" };
            (r.0.clone(), d, r.2, r.3, r.4, r.5)
        })
        .collect();
    the_caution(
        &positioning_cautions(&swapped),
        &["`direction`", "swapped", "time_min"],
    );

    // Run 2 pasted again as run 6 (with its times: they then overlap run 2's).
    let mut copied = clean.clone();
    copied.extend(
        clean
            .iter()
            .filter(|r| r.0 == "2")
            .map(|r| ("6".to_string(), r.1, r.2, r.3, r.4, r.5)),
    );
    let cautions = positioning_cautions(&copied);
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("run \"6\" holds the same 22 readings as run \"2\"")),
        "{cautions:#?}"
    );
    // … and its times (22 readings a run, 0.1 min apart) put it inside run 2's (2.3 … 4.4 min).
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("run \"6\" starts at 2.3 min, before run \"2\" ended at 4.4 min")),
        "{cautions:#?}"
    );
    assert_eq!(cautions.len(), 2, "{cautions:#?}");

    // The export cut in the middle of run 5's way down: 17 of its 22 readings.
    let cut = &clean[..clean.len() - 5];
    the_caution(
        &positioning_cautions(cut),
        &["run \"5\" has 17 of 22", "5 the report counts"],
    );

    // Seconds in time_min (6 min between readings) and hours (0.1 s).
    for (factor, expected) in [
        (60.0, "seconds in the minutes column"),
        (1.0 / 60.0, "hours in the minutes column"),
    ] {
        let scaled: Vec<_> = clean
            .iter()
            .map(|r| (r.0.clone(), r.1, r.2, r.3, r.4 * factor, r.5))
            .collect();
        the_caution(&positioning_cautions(&scaled), &["`time_min`", expected]);
    }

    // The air in °F: 20.2 °C reads 68.36.
    let fahrenheit: Vec<_> = clean
        .iter()
        .map(|r| (r.0.clone(), r.1, r.2, r.3, r.4, r.5 * 1.8 + 32.0))
        .collect();
    the_caution(
        &positioning_cautions(&fahrenheit),
        &["`temp_air_degc`", "68.36 °C", "°F"],
    );
}

/// A ball-bar trace of both senses (R 150 mm, 1000 mm/min, 250 Hz: 0.02546° a sample): a
/// 10 µm ellipse from a 20 µm/m squareness (sin 2θ·R·s/2 = 1.5 µm) and 0.2 µm of noise.
pub(super) fn ballbar_text(preamble: &str, rows: &[(&str, f64, f64, f64)]) -> String {
    let mut text = format!("{preamble}direction,angle_deg,deviation_um,time_s\n");
    for (sense, angle, deviation, time) in rows {
        text += &format!("{sense},{angle:.6},{deviation:.4},{time:.3}\n");
    }
    text
}

pub(super) const BALLBAR_PREAMBLE: &str = "# plane = XY\n# radius_mm = 150\n# feed_mm_per_min = 1000\n# sample_rate_hz = 250\n# first_direction = ccw\n";

pub(super) fn ballbar_rows() -> Vec<(&'static str, f64, f64, f64)> {
    let mut noise = Noise(11);
    let step_deg = (1000.0 / 60.0 / 150.0 / 250.0_f64).to_degrees();
    let n = (360.0 / step_deg) as usize;
    let mut rows = Vec::new();
    let mut t = 0.0;
    for sense in ["ccw", "cw"] {
        for k in 0..n {
            let angle = if sense == "ccw" {
                k as f64 * step_deg
            } else {
                (360.0 - k as f64 * step_deg).rem_euclid(360.0)
            };
            let deviation = 1.5 * (2.0 * angle.to_radians()).sin() + 0.2 * noise.next();
            t += 0.004;
            rows.push((sense, angle, deviation, t));
        }
    }
    rows
}

pub(super) fn ballbar_read(text: &str) -> Result<BallbarTable, String> {
    BallbarTable::parse(text.as_bytes(), "bar.csv").map_err(|e| e.to_string())
}

#[test]
fn ballbar_slips_are_refused_or_named_and_the_clean_table_is_not() {
    let test = CircularTest {
        plane: Plane::XY,
        radius: 0.150,
        feed: 1.0 / 60.0,
    };
    let clean = ballbar_rows();
    let table = ballbar_read(&ballbar_text(BALLBAR_PREAMBLE, &clean)).expect("reads");
    assert_eq!(
        ballbar_plausible::cautions(&table, &test),
        Vec::<String>::new()
    );

    // The senses swapped: the readings labelled ccw turn clockwise in time.
    let swapped: Vec<_> = clean
        .iter()
        .map(|r| (if r.0 == "ccw" { "cw" } else { "ccw" }, r.1, r.2, r.3))
        .collect();
    let text = ballbar_text(&BALLBAR_PREAMBLE.replace("ccw\n", "cw\n"), &swapped);
    let error = ballbar_read(&text).expect_err("refused");
    assert!(
        error.contains("bar.csv") && error.contains("senses are swapped"),
        "{error}"
    );

    // The whole trace appended to itself: each sense read twice at every instant.
    let twice: Vec<_> = clean.iter().chain(&clean).copied().collect();
    let error = ballbar_read(&ballbar_text(BALLBAR_PREAMBLE, &twice)).expect_err("refused");
    assert!(
        error.contains("`time_s`: a second ccw reading at 0.004 s (the first at line 7)")
            && error.contains("appended twice"),
        "{error}"
    );

    // time_s rescaled (ms read as s/2: the feed doubled in the export): 2 ms steps against
    // the preamble's 250 Hz.
    let halved: Vec<_> = clean.iter().map(|r| (r.0, r.1, r.2, r.3 / 2.0)).collect();
    let error = ballbar_read(&ballbar_text(BALLBAR_PREAMBLE, &halved)).expect_err("refused");
    assert!(
        error.contains("2 ms apart") && error.contains("says 4 ms"),
        "{error}"
    );

    // One sense only: 1 ms of servo mismatch reads as v·Δτ/R = (1000/60 mm/s · 1 ms) /
    // 150 mm = 111.1 µm/m of squareness.
    let ccw: Vec<_> = clean.iter().filter(|r| r.0 == "ccw").copied().collect();
    let table = ballbar_read(&ballbar_text(BALLBAR_PREAMBLE, &ccw)).expect("reads");
    the_caution(
        &ballbar_plausible::cautions(&table, &test),
        &["only the ccw sense", "111.1 µm/m"],
    );

    // Millimetres in the µm column: a trace spanning 3 nm, under the bar's resolution.
    let mm: Vec<_> = clean
        .iter()
        .map(|r| (r.0, r.1, r.2 / 1000.0, r.3))
        .collect();
    let table = ballbar_read(&ballbar_text(BALLBAR_PREAMBLE, &mm)).expect("reads");
    the_caution(
        &ballbar_plausible::cautions(&table, &test),
        &["`deviation_um`", "mm in the µm column"],
    );

    // No time_s: the preamble's radius and feed could not be checked, and the report says so.
    let untimed: String = ballbar_text(BALLBAR_PREAMBLE, &clean)
        .lines()
        .map(|l| {
            if l.starts_with('#') {
                l.to_string()
            } else {
                l.rsplit_once(',').unwrap().0.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let table = ballbar_read(&untimed).expect("reads");
    the_caution(
        &ballbar_plausible::cautions(&table, &test),
        &[
            "the preamble",
            "no time_s",
            "nothing in it could check them",
        ],
    );
}

/// A 5 h drift record read every minute: x grows 8 µm with a 60 min time constant, z 0.5 µm
/// linearly, 10 nm of noise; the air at 20 ± 0.3 °C.
fn drift_text(times: impl Fn(f64) -> f64, scale: f64, rows: usize, pasted: bool) -> String {
    let mut noise = Noise(3);
    let mut text = String::from("time_min,x_um,z_um,temp_air_degc\n");
    let mut lines = Vec::new();
    for k in 0..rows {
        let t = k as f64;
        let x = 8.0 * (1.0 - (-t / 60.0).exp()) + 0.01 * noise.next();
        let z = 0.5 * t / 300.0 + 0.01 * noise.next();
        let air = 20.0 + 0.3 * (t / 90.0).sin();
        lines.push((x * scale, z * scale, air));
    }
    if pasted {
        let first = lines[..rows / 2].to_vec();
        lines.truncate(rows / 2);
        lines.extend(first);
    }
    for (k, (x, z, air)) in lines.iter().enumerate() {
        text += &format!("{:.4},{x:.4},{z:.4},{air:.3}\n", times(k as f64));
    }
    text
}

pub(super) fn drift_cautions(text: &str) -> Vec<String> {
    let table = DriftTable::parse(text.as_bytes(), "nest.csv").expect("reads");
    drift_plausible::cautions(&table, 3600.0, table.conditions.spacing)
}

/// A 5 h record of a nest with two X sensors `spacing_mm` apart: x1 grows 6 µm (60 min time
/// constant), x2 the same plus 0.2 µm·(1 − e^{−t/90}) (a tilt of 2 µrad over 100 mm, within
/// the 10 % the unit check allows), z 1.75 µm linearly; 10 nm of noise. `x2_scale` and `z_scale` multiply what the file holds.
pub(super) fn nest_text(spacing_mm: f64, x2_scale: f64, z_scale: f64) -> String {
    let mut noise = Noise(11);
    let mut text = format!("# spacing_mm = {spacing_mm}\ntime_min,x1_um,x2_um,z_um\n");
    for k in 0..301 {
        let t = k as f64;
        let x1 = 6.0 * (1.0 - (-t / 60.0).exp()) + 0.01 * noise.next();
        let x2 = x1 + 0.2 * (1.0 - (-t / 90.0).exp()) + 0.01 * noise.next();
        let z = -1.75 * t / 300.0 + 0.01 * noise.next();
        text += &format!("{t},{x1:.4},{:.6},{:.7}\n", x2 * x2_scale, z * z_scale);
    }
    text
}

#[test]
fn drift_slips_are_named_and_the_clean_record_is_not() {
    let minutes = |t: f64| t;
    assert_eq!(
        drift_cautions(&drift_text(minutes, 1.0, 301, false)),
        Vec::<String>::new()
    );
    // nm in the µm columns: 8 µm of growth reads 8 mm.
    the_caution(
        &drift_cautions(&drift_text(minutes, 1000.0, 301, false)),
        &["`x_um`", "nm in the µm column"],
    );
    // mm in them: the widest channel spans 8 nm… and z half a nanometre: the widest decides.
    the_caution(
        &drift_cautions(&drift_text(minutes, 1e-3 / 2.0, 301, false)),
        &["span at most", "mm in the µm columns"],
    );
    // Hours in time_min: 300 min read as 5 min, shorter than the ETVE test.
    the_caution(
        &drift_cautions(&drift_text(|t| t / 60.0, 1.0, 301, false)),
        &["`time_min`", "lasts 5 min", "hours in the minutes column"],
    );
    // Seconds in it: a reading every 60 "min".
    the_caution(
        &drift_cautions(&drift_text(|t| t * 60.0, 1.0, 301, false)),
        &[
            "`time_min`",
            "60 min apart",
            "seconds in the minutes column",
        ],
    );
    // The first half pasted again as the second.
    the_caution(
        &drift_cautions(&drift_text(minutes, 1.0, 300, true)),
        &["from 150 min repeat those from 0 min", "pasted again"],
    );
    // A nest whose sensors tilt apart by 0.2 µm is clean; x2 read in counts of 0.1 µm (×10)
    // makes a tilt of (10·6.2 − 6)/100 mm ≈ 560 µrad, and is named against x1.
    assert_eq!(
        drift_cautions(&nest_text(100.0, 1.0, 1.0)),
        Vec::<String>::new()
    );
    the_caution(
        &drift_cautions(&nest_text(100.0, 10.0, 1.0)),
        &[
            "`x1_um` and `x2_um`",
            "x2 reads 10 times x1",
            "gain or unit",
        ],
    );
    // z alone in mm: 1.75 µm reads 1.75 nm while x1 spans 6 µm.
    the_caution(
        &drift_cautions(&nest_text(100.0, 1.0, 1e-3)),
        &["`z_um` spans 0.00", "mm in that column"],
    );
    // The spacing in inches (100 mm = 3.937 in): closer than any two sensors stand.
    the_caution(
        &drift_cautions(&nest_text(3.937, 1.0, 1.0)),
        &["spacing_mm 3.937", "25.4 times too large"],
    );
}

/// A 50 mm ring gauge probed at 36 points with a 1.5 mm stylus ball (bore: the stylus centre
/// at 23.5 mm, approaching outward), the centre at (500, 250, 30) mm.
fn ring_text(points: usize, arc_deg: f64, swap_ij: bool, cal_diameter: f64) -> String {
    let mut text = String::from(
        "# stylus_radius_mm = 1.5\ncycle,kind,feature,point,x_mm,y_mm,z_mm,i,j,k,cal_diameter_mm\n",
    );
    for p in 0..points {
        let a = (arc_deg * p as f64 / points as f64).to_radians();
        let (i, j) = (a.cos(), a.sin());
        let (i, j) = if swap_ij { (j, i) } else { (i, j) };
        text += &format!(
            "1,ring,1,{},{:.6},{:.6},30,{i:.9},{j:.9},0,{cal_diameter}\n",
            p + 1,
            500.0 + 23.5 * a.cos(),
            250.0 + 23.5 * a.sin()
        );
    }
    text
}

fn ring_cautions(text: &str) -> Vec<String> {
    let table = ProbeTable::parse(text.as_bytes(), "ring.csv").expect("reads");
    evaluate_probe(&table, 1.5e-3).expect("evaluates").cautions
}

#[test]
fn probe_set_up_slips_are_named_and_the_clean_ring_is_not() {
    assert_eq!(
        ring_cautions(&ring_text(36, 360.0, false, 50.0)),
        Vec::<String>::new()
    );
    // i and j swapped: (sin a, cos a) against the radius (cos a, sin a) stands off it by
    // arccos|sin 2a| = |90° − (2a mod 180°)|, over the 36 points (2a mod 180° = 0, 20 … 160°)
    // 90, 70, 50, 30, 10, 10, 30, 50, 70: a mean of 410°/9 = 45.6°.
    let cautions = ring_cautions(&ring_text(36, 360.0, true, 50.0));
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("45.6° off the feature's radius")),
        "{cautions:#?}"
    );
    // The radius in the diameter column: 25 mm off the calibration.
    the_caution(
        &ring_cautions(&ring_text(36, 360.0, false, 25.0)),
        &["differs from cal_diameter_mm by 25 mm"],
    );
    // The x of point 5 (at 40°) typed 0.1 mm off: 0.1·cos 40° = 77 µm along its radius, less
    // the little it pulls the fit; the other touches stay within a few µm of it.
    let typo = ring_text(36, 360.0, false, 50.0).replacen(
        &format!("1,ring,1,5,{:.6},", 500.0 + 23.5 * 40f64.to_radians().cos()),
        &format!(
            "1,ring,1,5,{:.6},",
            500.0 + 23.5 * 40f64.to_radians().cos() + 0.1
        ),
        1,
    );
    assert_ne!(typo, ring_text(36, 360.0, false, 50.0), "point 5 moved");
    let cautions = ring_cautions(&typo);
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("point 5 lies") && c.contains("mistyped or dirty touch")),
        "{cautions:#?}"
    );

    // Ten points over 100°: the arc from the first to the last touch is 90°.
    the_caution(
        &ring_cautions(&ring_text(10, 100.0, false, 50.0)),
        &["span only 90° of the ring"],
    );
}

/// An R-test export of the probe readings alone (no commanded positions): C turned 0 … 360° in
/// 10° steps, A swung 0 … −90° in 15° steps, deviations a 10 µm circle and a 5 µm sag, and a
/// copy of the C circle under another name.
pub(super) fn rtest_text(to_file: impl Fn(f64) -> f64, pasted: bool) -> String {
    let mut text = String::from("test,a_deg,c_deg,dx_um,dy_um,dz_um\n");
    let mut noise = Noise(5);
    let mut circle = String::new();
    for k in 0..=36 {
        let c = 10.0 * k as f64;
        let (s, co) = c.to_radians().sin_cos();
        circle += &format!(
            "{{NAME}},{},{},{:.4},{:.4},{:.4}\n",
            to_file(0.0),
            to_file(c),
            10.0 * (co - 1.0) + 0.2 * noise.next(),
            10.0 * s + 0.2 * noise.next(),
            0.2 * noise.next()
        );
    }
    text += &circle.replace("{NAME}", "C circle");
    for k in 0..=6 {
        let a = -15.0 * k as f64;
        text += &format!(
            "A swing,{},0,{:.4},0,{:.4}\n",
            to_file(a),
            0.2 * noise.next(),
            -5.0 * (a / 90.0).powi(2)
        );
    }
    if pasted {
        text += &circle.replace("{NAME}", "C circle again");
    }
    text
}

pub(super) fn rtest_cautions(text: &str) -> Vec<String> {
    let table =
        mtwin::kinds::rtest::RtestTable::parse(text.as_bytes(), "rtest.csv").expect("reads");
    mtwin::kinds::rtest::plausible::cautions(&table)
}

#[test]
fn rtest_radians_without_positions_and_a_pasted_test_are_named() {
    assert_eq!(
        rtest_cautions(&rtest_text(|d| d, false)),
        Vec::<String>::new()
    );
    // Radians: C's turn reads 0 … 6.2832, A's swing 0 … −1.5708; the widest sweep is C's.
    the_caution(
        &rtest_cautions(&rtest_text(f64::to_radians, false)),
        &[
            "`c_deg`",
            "test \"C circle\" sweeps 6.283",
            "radians in the degree columns",
        ],
    );
    the_caution(
        &rtest_cautions(&rtest_text(|d| d, true)),
        &["test \"C circle again\" holds the same 111 readings as test \"C circle\""],
    );
}

/// The foreign spindle export of `tests/data/spindle` (another analyser's column order, 32
/// samples a revolution, error motions of tenths of a µm, 4 µm of eccentricity; no probe
/// directions, so each probe reads along +X, +Y or +Z) with `edit(column, row, value)` applied
/// to every probe reading (rows counted from 0 after the header).
pub(super) fn spindle_cautions(edit: impl Fn(&str, usize, f64) -> f64) -> Vec<String> {
    use mtwin::kinds::spindle::{evaluate::Options, evaluate::evaluate, plausible, table};
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/spindle/foreign_sea.csv");
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = String::new();
    let mut names: Vec<String> = Vec::new();
    let mut row = 0;
    for line in text.lines() {
        if line.starts_with('#') {
            out += &format!("{line}\n");
        } else if names.is_empty() {
            names = line.split(',').map(str::to_string).collect();
            out += &format!("{line}\n");
        } else {
            let fields: Vec<String> = line
                .split(',')
                .zip(&names)
                .map(|(f, name)| match name.ends_with("_um") {
                    true => format!("{}", edit(name, row, f.parse::<f64>().unwrap())),
                    false => f.to_string(),
                })
                .collect();
            out += &format!("{}\n", fields.join(","));
            row += 1;
        }
    }
    let table = table::parse(out.as_bytes(), "sea.csv").expect("reads");
    let evaluation = evaluate(
        &table.record,
        table.samples_per_revolution,
        &Options::default(),
    )
    .expect("evaluates");
    plausible::cautions(&table.record, &evaluation)
}

#[test]
fn spindle_records_in_nm_or_mm_are_named() {
    // Its error motions are 0.1 … 0.3 µm (radial and axial; the tilt is not judged).
    assert_eq!(spindle_cautions(|_, _, v| v), Vec::<String>::new());
    the_caution(
        &spindle_cautions(|_, _, v| v * 1000.0),
        &["more than the 100 µm", "nm in the µm columns"],
    );
    the_caution(
        &spindle_cautions(|_, _, v| v * 1e-3),
        &["below 0.005 µm", "mm in the µm columns"],
    );
    // The axial probe alone in mm: its 0.1 µm read as 0.1 nm, the radial probes span 9 µm.
    the_caution(
        &spindle_cautions(|name, _, v| if name == "z_um" { v * 1e-3 } else { v }),
        &["`z_um` spans 0.000", "mm in that column"],
    );
}

#[test]
fn a_radial_probe_read_from_the_other_side_turns_the_eccentricity_against_the_axis() {
    // The 4 µm eccentricity turns with the angle on x1 and y1 (x ≈ 4 cos θ, y ≈ 4 sin θ). With
    // x1 read from the −X side (its sign reversed), the centre turns against the angle: the
    // co-rotating part falls to the error motions' tenths and the counter-rotating is ~4 µm.
    let flipped = spindle_cautions(|name, _, v| if name == "x1_um" { -v } else { v });
    the_caution(
        &flipped,
        &["probes y1 and x1", "turns against the axis", "wrong sign"],
    );
    assert!(
        flipped.iter().all(|c| !c.contains("x2 and y2")),
        "{flipped:?}"
    );
}
