//! One disturbed reading, a stuck sensor and a preamble that contradicts its record: each test
//! takes a clean table built by hand (the helpers of [`super::plausible`]), checks it passes,
//! disturbs it as an instrument or an export does, and checks the caution names where.

use super::plausible::{
    BALLBAR_PREAMBLE, Noise, ballbar_read, ballbar_rows, ballbar_text, drift_cautions, nest_text,
    positioning_cautions, positioning_rows, rtest_cautions, rtest_text, spindle_cautions,
    the_caution,
};

#[test]
fn one_laser_reading_off_is_named_and_a_run_offset_as_a_whole_is_not() {
    let clean = positioning_rows();
    // Run 3 on its way down at 350 mm: the beam interrupted, +150 µm kept in the export. The
    // other runs there lie within 0.2 µm (noise ±0.1 µm), so it lies 150 µm from their median.
    let glitch: Vec<_> = clean
        .iter()
        .map(|r| {
            let hit = r.0 == "3" && r.1 == "-" && r.2 == 350.0;
            (
                r.0.clone(),
                r.1,
                r.2,
                r.3 + if hit { 150.0 } else { 0.0 },
                r.4,
                r.5,
            )
        })
        .collect();
    let cautions = positioning_cautions(&glitch);
    assert!(
        cautions.iter().any(
            |c| c.contains("run \"3\", − direction at target 350 mm reads 150.")
                && c.contains("a beam interrupted")
        ),
        "{cautions:#?}"
    );
    // Run 4 re-zeroed: every reading of it 2 µm up. No single reading is named for it.
    let offset: Vec<_> = clean
        .iter()
        .map(|r| {
            let d = if r.0 == "4" { r.3 + 2.0 } else { r.3 };
            (r.0.clone(), r.1, r.2, d, r.4, r.5)
        })
        .collect();
    let cautions = positioning_cautions(&offset);
    assert!(
        cautions.iter().all(|c| !c.contains("alone sets R and A")),
        "{cautions:#?}"
    );
}

/// `rtest_text` with the C circle's pose at `c_deg` moved by `dx` µm in X and the test renamed.
fn rtest_edited(c_deg: &str, dx: f64, name: &str) -> String {
    rtest_text(|v| v, false)
        .lines()
        .map(|line| {
            let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
            if fields[0] == "C circle" {
                if fields[2] == c_deg {
                    fields[3] = format!("{:.4}", fields[3].parse::<f64>().unwrap() + dx);
                }
                fields[0] = name.to_string();
            }
            fields.join(",") + "\n"
        })
        .collect()
}

#[test]
fn a_chip_on_the_nest_at_one_pose_and_a_test_named_for_another_angle_are_named() {
    assert_eq!(
        rtest_cautions(&rtest_edited("200", 0.0, "C circle")),
        Vec::<String>::new()
    );
    // +30 µm at C = 200°, the 21st pose: its neighbours' mean differs from it by 30 µm, less
    // the circle's own bend (10 µm·(1 − cos 10°) = 0.15 µm) and the noise (±0.2 µm a reading).
    the_caution(
        &rtest_cautions(&rtest_edited("200", 30.0, "C circle")),
        &[
            "test \"C circle\": pose 21 in file order lies 29.8",
            "chip on the nest",
        ],
    );
    // The C circle named for A = −45° while its a_deg holds 0 all through.
    the_caution(
        &rtest_cautions(&rtest_edited("200", 0.0, "CK1 A-45")),
        &["test \"CK1 A-45\"", "says A-45 but `a_deg` holds 0"],
    );
}

#[test]
fn a_drift_sensor_that_stops_changing_is_named() {
    // x1 frozen at its 199 min value to the end: 102 readings of one value.
    let frozen: String = nest_text(100.0, 1.0, 1.0)
        .lines()
        .map(|line| line.split(',').map(str::to_string).collect::<Vec<_>>())
        .scan(String::new(), |held, mut fields| {
            if let Ok(t) = fields[0].parse::<f64>() {
                if t == 199.0 {
                    *held = fields[1].clone();
                } else if t > 199.0 {
                    fields[1] = held.clone();
                }
            }
            Some(fields.join(",") + "\n")
        })
        .collect();
    let cautions = drift_cautions(&frozen);
    assert!(
        cautions.iter().any(|c| c.contains("`x1_um` holds")
            && c.contains("from 199 to 300 min (102 readings)")
            && c.contains("out of its range")),
        "{cautions:#?}"
    );
}

/// A spindle thermal test that ran 240 min at speed and stood 60 (stated as `run_min`,
/// `stop_min`): the bearing warms 12 °C with a 30 min time constant and cools with 40 min
/// after the stop, Z grows 3 µm; the air at 20 ± 0.2 °C. `ambient` names the ambient sensor.
fn spindle_test_text(run_min: f64, stop_min: f64, ambient: &str) -> String {
    let mut noise = Noise(13);
    let mut text = format!(
        "# test = iso230_3_spindle\n# run_min = {run_min}\n# stop_min = {stop_min}\n\
         # ambient_sensor = {ambient}\n\
         time_min,x1_um,z_um,temp_air_degc,temp_bearing_degc\n"
    );
    let warm = |t: f64| 1.0 - (-t / 30.0).exp();
    for k in 0..=300 {
        let t = k as f64;
        let heat = if t <= 240.0 {
            warm(t)
        } else {
            warm(240.0) * (-(t - 240.0) / 40.0).exp()
        };
        text += &format!(
            "{t},{:.4},{:.4},{:.3},{:.3}\n",
            0.01 * noise.next(),
            -3.0 * heat + 0.01 * noise.next(),
            20.0 + 0.2 * (t / 50.0).sin(),
            20.0 + 12.0 * heat
        );
    }
    text
}

#[test]
fn a_running_period_that_contradicts_the_temperatures_or_a_structure_sensor_as_ambient_is_named() {
    assert_eq!(
        drift_cautions(&spindle_test_text(240.0, 60.0, "air")),
        Vec::<String>::new()
    );
    // run_min and stop_min exchanged: the bearing is hottest at 240 min, 180 min after the
    // stated end of the run, later than 60 + 240/2 = 180 min.
    the_caution(
        &drift_cautions(&spindle_test_text(60.0, 240.0, "air")),
        &[
            "`temp_bearing_degc` is hottest at 240 min",
            "180 min after",
            "run_min and stop_min exchanged",
        ],
    );
    // The bearing sensor named as the ambient one while the table has an air sensor.
    the_caution(
        &drift_cautions(&spindle_test_text(240.0, 60.0, "bearing")),
        &["`temp_bearing_degc` while the table has `temp_air_degc`"],
    );
}

#[test]
fn a_spindle_probe_saturated_through_revolutions_is_named() {
    // x2 held at −5 µm (its range's end) from sample 32 to 95: two of the four revolutions of
    // 32 samples.
    let cautions = spindle_cautions(|name, row, v| {
        if name == "x2_um" && (32..96).contains(&row) {
            -5.0
        } else {
            v
        }
    });
    assert!(
        cautions.iter().any(|c| c
            .contains("`x2_um` holds -5 µm unchanged for 64 samples (2 revolutions)")
            && c.contains("saturated")),
        "{cautions:#?}"
    );
}

/// A 3 × 3 ball plate (20 mm balls, 80 mm pitch) placed at (220, 85, 20) mm, each ball touched
/// at four points 30° below its equator and once on top with a 2 mm stylus, the machine's X
/// reading 20 µm/m long and 0.3 µm of noise; `cal_typo` adds to ball 7's calibrated X (mm).
fn plate_text(cal_typo: f64) -> String {
    let mut noise = Noise(17);
    let mut text = String::from(
        "# stylus_radius_mm = 2\n\
         cycle,kind,feature,point,x_mm,y_mm,z_mm,i,j,k,cal_diameter_mm,cal_x_mm,cal_y_mm,cal_z_mm\n",
    );
    let (s, c) = 30f64.to_radians().sin_cos();
    let approaches = [
        (-c, 0.0, -s),
        (0.0, -c, -s),
        (c, 0.0, -s),
        (0.0, c, -s),
        (0.0, 0.0, -1.0),
    ];
    for ball in 0..9 {
        let cal = [80.0 * (ball % 3) as f64, 80.0 * (ball / 3) as f64, 0.0];
        let centre = [220.0 + cal[0] * (1.0 + 20e-6), 85.0 + cal[1], 20.0 + cal[2]];
        let cal_x = cal[0] + if ball == 6 { cal_typo } else { 0.0 };
        for (p, (i, j, k)) in approaches.iter().enumerate() {
            // The stylus centre latched at ball radius + stylus radius against the approach.
            let mut at = |q: usize, e: f64| centre[q] - 12.0 * e + 0.3e-3 * noise.next();
            text += &format!(
                "1,plate,{},{},{:.6},{:.6},{:.6},{i:.9},{j:.9},{k:.9},20,{cal_x:.6},{:.6},0\n",
                ball + 1,
                p + 1,
                at(0, *i),
                at(1, *j),
                at(2, *k),
                cal[1]
            );
        }
    }
    text
}

#[test]
fn a_ball_plate_certificate_value_typed_wrong_is_named() {
    let cautions = |text: &str| {
        let table = mtwin::kinds::probe::table::ProbeTable::parse(text.as_bytes(), "plate.csv")
            .expect("reads");
        mtwin::kinds::probe::analysis::evaluate(&table, 2e-3)
            .expect("evaluates")
            .cautions
    };
    // The machine's 20 µm/m changes the distances smoothly, 3.2 µm at most over 160 mm: no
    // ball stands out.
    assert_eq!(cautions(&plate_text(0.0)), Vec::<String>::new());
    // Ball 7's X typed 0.1 mm long: its distances to the others are off by up to 100 µm
    // (along X; less across), the other pairs by the machine's few µm.
    the_caution(
        &cautions(&plate_text(0.1)),
        &[
            "cycle 1: ball 7's distances",
            "calibrated centre",
            "mistyped",
        ],
    );
}

#[test]
fn rows_in_another_order_are_read_as_measured_and_a_laser_re_zeroed_each_run_is_named() {
    let clean = positioning_rows();
    // The rows listed run by run from the last (an export sorted otherwise), times intact:
    // the runs were read one after the other all the same.
    let mut reordered = clean.clone();
    reordered.sort_by(|a, b| b.0.cmp(&a.0).then(a.4.total_cmp(&b.4)));
    assert_eq!(positioning_cautions(&reordered), Vec::<String>::new());
    // Each run's first reading subtracted from the run: the laser re-zeroed at each run.
    let zeroed: Vec<_> = clean
        .iter()
        .map(|r| {
            let first = clean.iter().find(|f| f.0 == r.0).unwrap().3;
            (r.0.clone(), r.1, r.2, r.3 - first, r.4, r.5)
        })
        .collect();
    let cautions = positioning_cautions(&zeroed);
    assert!(
        cautions.iter().any(|c| c.contains(
            "every one of the 5 runs starts on exactly 0 while the preamble does not say"
        )),
        "{cautions:#?}"
    );
}

#[test]
fn a_drift_glitch_a_re_zeroed_sensor_and_a_dead_thermometer_are_named() {
    // z +15 µm at 150 min alone.
    let edit = |column: usize, from: f64, to: f64, by: f64| -> String {
        nest_text(100.0, 1.0, 1.0)
            .lines()
            .map(|line| {
                let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
                if let Ok(t) = fields[0].parse::<f64>()
                    && (from..=to).contains(&t)
                {
                    fields[column] = format!("{:.7}", fields[column].parse::<f64>().unwrap() + by);
                }
                fields.join(",") + "\n"
            })
            .collect()
    };
    let cautions = drift_cautions(&edit(3, 150.0, 150.0, 15.0));
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("`z_um`: the reading at 150 min stands 14.9")
                && c.contains("glitch")),
        "{cautions:#?}"
    );
    // x2 re-zeroed at 240 min: 4.4 µm lower from there, x1 goes on.
    let cautions = drift_cautions(&edit(2, 240.0, 300.0, -4.4));
    assert!(
        cautions.iter().any(
            |c| c.contains("`x1_um` and `x2_um`: their difference steps by -4.4")
                && c.contains("between 239 and 240 min")
        ),
        "{cautions:#?}"
    );
    // The air sensor reading 20.01 °C through the whole 300 min.
    let dead: String = spindle_test_text(240.0, 60.0, "air")
        .lines()
        .map(|line| {
            let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
            if fields[0].parse::<f64>().is_ok() {
                fields[3] = "20.010".into();
            }
            fields.join(",") + "\n"
        })
        .collect();
    the_caution(
        &drift_cautions(&dead),
        &["`temp_air_degc` holds 20.01 °C through the whole 300 min record"],
    );
}

#[test]
fn a_one_sample_spike_is_named_on_a_spindle_and_a_ball_bar_and_a_sphere_touch_by_its_form() {
    let cautions = spindle_cautions(|name, row, v| {
        if name == "y1_um" && row == 50 {
            v + 3.0
        } else {
            v
        }
    });
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("`y1_um`: sample 51") && c.contains("stands 2.98")),
        "{cautions:#?}"
    );
    // One ball-bar reading +40 µm; the reversal spikes of a real trace rise over several.
    let test = mtwin::kinds::ballbar::iso230_4::CircularTest {
        plane: mtwin::machine::Plane::XY,
        radius: 0.150,
        feed: 1.0 / 60.0,
    };
    let mut rows = ballbar_rows();
    rows[300].2 += 40.0;
    let table = ballbar_read(&ballbar_text(BALLBAR_PREAMBLE, &rows)).expect("reads");
    let cautions = mtwin::kinds::ballbar::plausible::cautions(&table, &test);
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("reading 301 stands 40.") || c.contains("reading 301 stands 39.")),
        "{cautions:#?}"
    );
    // One touch of plate ball 3 20 µm off along X: its five-touch fit spreads it, the form
    // grows to µm where the other balls' is their 0.3 µm noise.
    let plate: String = plate_text(0.0)
        .lines()
        .map(|line| {
            let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
            if fields.len() > 3 && fields[2] == "3" && fields[3] == "1" {
                fields[4] = format!("{:.6}", fields[4].parse::<f64>().unwrap() + 0.020);
            }
            fields.join(",") + "\n"
        })
        .collect();
    let table = mtwin::kinds::probe::table::ProbeTable::parse(plate.as_bytes(), "plate.csv")
        .expect("reads");
    let cautions = mtwin::kinds::probe::analysis::evaluate(&table, 2e-3)
        .expect("evaluates")
        .cautions;
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("cycle 1 feature 3: the touches' radii span")
                && c.contains("one touch off")),
        "{cautions:#?}"
    );
}

#[test]
fn an_r_test_probe_stuck_through_poses_is_named() {
    // dy of the C circle held from pose 21 to the end (17 poses).
    let mut held = String::new();
    let stuck: String = rtest_text(|v| v, false)
        .lines()
        .enumerate()
        .map(|(row, line)| {
            let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
            if fields[0] == "C circle" {
                if row == 21 {
                    held = fields[4].clone();
                } else if row > 21 {
                    fields[4] = held.clone();
                }
            }
            fields.join(",") + "\n"
        })
        .collect();
    let cautions = rtest_cautions(&stuck);
    assert!(
        cautions
            .iter()
            .any(|c| c.contains("test \"C circle\": `dy_um` holds")
                && c.contains("from pose 21 to 37 (17 poses)")),
        "{cautions:#?}"
    );
}

#[test]
fn a_drift_record_listed_newest_first_reads_as_measured_and_a_time_given_twice_is_refused() {
    use mtwin::kinds::drift::table::DriftTable;
    let text = nest_text(100.0, 1.0, 1.0);
    let mut lines: Vec<&str> = text.lines().collect();
    let header = lines
        .iter()
        .position(|l| l.starts_with("time_min"))
        .unwrap();
    lines[header + 1..].reverse();
    let reversed = lines.join("\n") + "\n";
    let read = |t: &str| DriftTable::parse(t.as_bytes(), "nest.csv");
    assert_eq!(read(&reversed).unwrap(), read(&text).unwrap());
    // The row of 150 min given again after the others.
    let again = lines
        .iter()
        .find(|l| l.starts_with("150,"))
        .unwrap()
        .to_string();
    let error = read(&(reversed + &again + "\n")).unwrap_err().to_string();
    assert!(
        error.contains("a second reading at 150 min") && error.contains("pasted again"),
        "{error}"
    );
}

/// An R-test table with raw probe readings, built from the nest's geometry written out here:
/// three probes at azimuths 0°, 120°, 240°, each axis (from the sphere centre out to the probe)
/// asin(1/√3) above the plane normal to the tool, reading aᵢ·v + offset with v = −d the
/// sphere's move relative to the nest. `dz_sign`, `d_sign` then rewrite the deviations as a
/// file in another convention would hold them.
fn rtest_with_probes(d_sign: f64, dz_sign: f64) -> String {
    let elevation = (1.0 / 3f64.sqrt()).asin();
    let axes: Vec<[f64; 3]> = (0..3)
        .map(|i| {
            let azimuth = (120.0 * i as f64).to_radians();
            [
                elevation.cos() * azimuth.cos(),
                elevation.cos() * azimuth.sin(),
                elevation.sin(),
            ]
        })
        .collect();
    let mut noise = super::plausible::Noise(17);
    let mut text = String::from("test,c_deg,dx_um,dy_um,dz_um,probe1_um,probe2_um,probe3_um\n");
    for (name, tilt) in [("C circle", 4.0), ("C circle B", -3.0)] {
        for k in 0..=36 {
            let c = (10.0 * k as f64).to_radians();
            // A K4-like circle, and a sag twice a turn that dx, dy cannot mimic.
            let d = [
                10.0 * (c.cos() - 1.0),
                10.0 * c.sin(),
                tilt * (2.0 * c).sin(),
            ];
            let probes: Vec<String> = axes
                .iter()
                .enumerate()
                .map(|(i, a)| {
                    let along = -(a[0] * d[0] + a[1] * d[1] + a[2] * d[2]);
                    format!("{:.3}", along - 9.0 + i as f64 + 0.02 * noise.next())
                })
                .collect();
            text += &format!(
                "{name},{},{:.4},{:.4},{:.4},{}\n",
                10 * k,
                d_sign * d[0],
                d_sign * d[1],
                d_sign * dz_sign * d[2],
                probes.join(",")
            );
        }
    }
    text
}

#[test]
fn deviations_in_the_other_sign_convention_than_the_probes_are_refused() {
    use mtwin::kinds::rtest::RtestTable;
    let clean = RtestTable::parse(rtest_with_probes(1.0, 1.0).as_bytes(), "r.csv");
    assert!(clean.is_ok(), "{:?}", clean.err());
    // The sphere relative to the tool (every deviation negated), or dz alone flipped: the
    // probes' sum rises with dz by √3 (three probes each sin(35.26°) = 1/√3 along the tool).
    for (d_sign, dz_sign) in [(-1.0, 1.0), (1.0, -1.0)] {
        let error = RtestTable::parse(rtest_with_probes(d_sign, dz_sign).as_bytes(), "r.csv")
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with(
                "r.csv: the probes' readings rise with dz_um (test \"C circle\": their sum 1.73"
            ),
            "{error}"
        );
    }
}

#[test]
fn a_laser_without_air_compensation_in_warm_air_is_named_with_its_scale_error() {
    use mtwin::kinds::positioning::{PositioningTable, plausible};
    // The clean rows with the air logged at 24.1 °C, the laser compensating nothing.
    let warm: Vec<_> = positioning_rows()
        .into_iter()
        .map(|(run, d, t, dev, time, _)| (run, d, t, dev, time, 24.1))
        .collect();
    let text = format!(
        "# compensation = none\n{}",
        super::plausible::positioning_text(&warm)
    );
    let table = PositioningTable::parse(text.as_bytes(), "laser.csv").unwrap();
    let cautions = plausible::cautions(&table);
    let caution = cautions
        .iter()
        .find(|c| c.starts_with("compensation = none"))
        .unwrap_or_else(|| panic!("{cautions:#?}"));
    // n − 1 = 2.71e-4 at 20 °C falls as 1/(1 + 0.003661 t) (an ideal gas at constant
    // pressure): 2.71e-4 · (1 − 1.07322/1.08823) = 3.74 ppm; the wetter air at 50 %RH adds
    // about 0.06 ppm. Over the 500 mm measured: 1.9 µm.
    let ppm: f64 = caution
        .split(" ppm short")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("{caution}"));
    assert!((3.7..3.95).contains(&ppm), "{caution}");
    assert!(caution.contains("over the 500 mm measured"), "{caution}");
    // Compensated, or at 20.2 °C (0.19 ppm, 0.09 µm over 500 mm), nothing is said.
    let compensated = text.replace("compensation = none", "compensation = air");
    let table = PositioningTable::parse(compensated.as_bytes(), "laser.csv").unwrap();
    assert!(plausible::cautions(&table).is_empty());
    let cool = format!(
        "# compensation = none\n{}",
        super::plausible::positioning_text(&positioning_rows())
    );
    let table = PositioningTable::parse(cool.as_bytes(), "laser.csv").unwrap();
    assert!(plausible::cautions(&table).is_empty());
}

#[test]
fn two_spindle_probes_on_one_signal_are_named() {
    let clean = super::plausible::spindle_cautions(|_, _, v| v);
    assert!(clean.is_empty(), "{clean:#?}");
    // The foreign analyser's export with its second probe's readings replaced by the first's
    // plus 3 µm (one probe on two inputs, the second with its own stand-off), then by the
    // first's negated.
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/spindle/foreign_sea.csv");
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let names: Vec<&str> = lines.next().unwrap().split(',').collect();
    let probes: Vec<usize> = (0..names.len())
        .filter(|&i| names[i].ends_with("_um"))
        .collect();
    let (first, second) = (names[probes[0]], names[probes[1]]);
    let readings: Vec<f64> = lines
        .map(|l| l.split(',').nth(probes[0]).unwrap().parse().unwrap())
        .collect();
    for (sign, words) in [(1.0, "but for an offset"), (-1.0, "the other negated")] {
        let cautions = super::plausible::spindle_cautions(|column, row, v| {
            if column == second {
                sign * readings[row] + 3.0
            } else {
                v
            }
        });
        the_caution(
            &cautions,
            &[
                &format!("columns `{first}` and `{second}` carry one signal"),
                words,
            ],
        );
    }
}

/// Twelve revolutions of two probes, x1 and y1, 32 samples each at 600 rpm: 3 µm of
/// eccentricity, 0.02 µm of noise; `gain(probe, revolution)` scales each reading.
fn eccentric_record(gain: impl Fn(&str, usize) -> f64) -> Vec<String> {
    use mtwin::kinds::spindle::{plausible, table};
    let mut noise = super::plausible::Noise(23);
    let mut text = String::from("time_s,revolution,angle_deg,x1_um,y1_um\n");
    for revolution in 0..12 {
        for k in 0..32 {
            let angle = 360.0 * k as f64 / 32.0;
            let t = (revolution * 32 + k) as f64 * 0.1 / 32.0;
            let (s, c) = angle.to_radians().sin_cos();
            text += &format!(
                "{t:.6},{revolution},{angle},{:.4},{:.4}\n",
                gain("x1", revolution) * (3.0 * c + 0.02 * noise.next()),
                gain("y1", revolution) * (3.0 * s + 0.02 * noise.next())
            );
        }
    }
    let table = table::parse(text.as_bytes(), "s.csv").unwrap_or_else(|e| panic!("{e}"));
    plausible::record_cautions(&table.record, table.samples_per_revolution)
}

#[test]
fn a_probe_range_switched_mid_record_is_named_by_its_revolution() {
    assert_eq!(eccentric_record(|_, _| 1.0), Vec::<String>::new());
    // Probe x1's amplifier switched to half gain from revolution 5 on.
    let cautions = eccentric_record(|p, r| if p == "x1" && r >= 5 { 0.5 } else { 1.0 });
    the_caution(
        &cautions,
        &[
            "column `x1_um`",
            "changes 0.5-fold from revolution 5",
            "range or gain switched",
        ],
    );
    // Both probes at half gain from there (the artefact's set-up changed for all): not named.
    let all = eccentric_record(|_, r| if r >= 5 { 0.5 } else { 1.0 });
    assert!(all.iter().all(|c| !c.contains("-fold")), "{all:#?}");
}
