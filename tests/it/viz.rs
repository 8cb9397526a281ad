//! Teaching scenes (feature `viz`): each lesson is recorded to memory, decoded back from the
//! `.rrd` bytes and checked: the entities exist, counts match the programme, and logged values
//! agree with the ground truth — the error arrows are exactly the magnification times the
//! twin's deviation, in the workpiece frame, placed where the URDF puts the tool by hand.
#![cfg(feature = "viz")]

use mtwin::app::{Scenario, Simulation, simulate};
use mtwin::viz::rr as rerun;
use mtwin::viz::{self, TIMELINE};
use rerun::external::re_log_encoding::DecoderApp;
use rerun::log::{Chunk, LogMsg};
use std::collections::BTreeMap;

/// A decoded recording: its data chunks.
struct Recording {
    chunks: Vec<Chunk>,
}

fn record(name: &str) -> (Scenario, Simulation, Recording) {
    let scenario = Scenario::load(format!("scenarios/{name}")).unwrap();
    let simulation = simulate(&scenario).unwrap();
    let (rec, storage) = rerun::RecordingStreamBuilder::new("mtwin-test")
        .enabled(true)
        .send_properties(false)
        .memory()
        .unwrap();
    mtwin::app::record::record(&rec, &scenario, &simulation, &mut |_| {}).unwrap();
    rec.flush_blocking().unwrap();
    let bytes = storage.drain_as_bytes().unwrap();
    let mut chunks = Vec::new();
    for message in DecoderApp::decode_eager(std::io::Cursor::new(bytes.as_slice())).unwrap() {
        if let LogMsg::ArrowMsg(store, arrow) = message.unwrap()
            && store.is_recording()
        {
            chunks.push(Chunk::from_arrow_msg(&arrow).unwrap());
        }
    }
    (scenario, simulation, Recording { chunks })
}

impl Recording {
    fn of(&self, entity: &str) -> impl Iterator<Item = &Chunk> {
        let path = rerun::EntityPath::from(entity);
        self.chunks.iter().filter(move |c| c.entity_path() == &path)
    }

    /// Rows logged on `entity` (static or on the timeline).
    fn rows(&self, entity: &str) -> usize {
        self.of(entity).map(|c| c.num_rows()).sum()
    }

    fn entities(&self) -> Vec<String> {
        let mut names: Vec<String> = self
            .chunks
            .iter()
            .map(|c| c.entity_path().to_string())
            .collect();
        names.sort();
        names.dedup();
        names
    }

    /// `(time s, value)` of a Scalars entity, in time order.
    fn scalars(&self, entity: &str) -> Vec<(f64, f64)> {
        let id = rerun::Scalars::descriptor_scalars().component;
        let mut out = Vec::new();
        for chunk in self.of(entity) {
            let times = chunk.iter_component_indices(rerun::TimelineName::from(TIMELINE), id);
            for ((time, _), values) in times.zip(chunk.iter_slices::<f64>(id)) {
                out.push((time.as_i64() as f64 * 1e-9, values[0]));
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out
    }

    /// `(time s, origin, vector)` of the first arrow of each row of an Arrows3D entity.
    fn arrows(&self, entity: &str) -> Vec<(f64, [f32; 3], [f32; 3])> {
        let vectors = rerun::Arrows3D::descriptor_vectors().component;
        let origins = rerun::Arrows3D::descriptor_origins().component;
        let mut out = Vec::new();
        for chunk in self.of(entity) {
            let times = chunk.iter_component_indices(rerun::TimelineName::from(TIMELINE), vectors);
            let v = chunk.iter_component::<rerun::components::Vector3D>(vectors);
            let o = chunk.iter_component::<rerun::components::Position3D>(origins);
            for (((time, _), v), o) in times.zip(v).zip(o) {
                out.push((time.as_i64() as f64 * 1e-9, v[0].0.0, o[0].0.0));
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out
    }

    /// `(time s, translation)` of a Transform3D entity, in time order.
    fn translations(&self, entity: &str) -> Vec<(f64, [f32; 3])> {
        let id = rerun::Transform3D::descriptor_translation().component;
        let mut out = Vec::new();
        for chunk in self.of(entity) {
            let times = chunk.iter_component_indices(rerun::TimelineName::from(TIMELINE), id);
            let values = chunk.iter_component::<rerun::components::Translation3D>(id);
            for ((time, _), v) in times.zip(values) {
                out.push((time.as_i64() as f64 * 1e-9, v[0].0.0));
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out
    }

    fn text(&self, entity: &str) -> String {
        let id = rerun::TextDocument::descriptor_text().component;
        self.of(entity)
            .flat_map(|c| {
                c.iter_slices::<String>(id)
                    .flatten()
                    .map(|s| s.to_string())
                    .collect::<Vec<_>>()
            })
            .collect()
    }
}

/// f32 scenes: a value of magnitude ~1 m carries ~1e-7 m of rounding; on an enlarged arrow
/// that is 0.1 µm / magnification of the truth (0.02 nm at ×5000).
const F32_M: f64 = 1e-7;

fn near(a: [f32; 3], b: [f64; 3], tolerance: f64) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (*x as f64 - y).abs() <= tolerance)
}

#[test]
fn abbe_lesson_arrows_are_the_magnified_truth_in_the_workpiece_frame() {
    let (scenario, simulation, recording) = record("teach_abbe.toml");
    let run = simulation.laser.as_ref().unwrap();
    let m = scenario.lesson.as_ref().unwrap().magnification;
    assert_eq!(m, 5000.0);
    let arrow_path = viz::tool_tip_error(m);
    assert_eq!(arrow_path, "world/workpiece_nominal/tool_tip_error_x5000");
    assert!(arrow_path.starts_with(viz::WORKPIECE_NOMINAL));
    // Without a thermal model the actual pose is known at every frame: arrows at every frame
    // and at each of the 2 runs × 6 targets × 2 directions readings, there equal to the
    // simulation's truth.
    let arrows = recording.arrows(&arrow_path);
    assert_eq!(run.visits.len(), 24);
    assert!(arrows.len() > 24);
    let workpiece = recording.translations(viz::WORKPIECE_NOMINAL);
    for (visit, pose) in run.visits.iter().zip(&run.poses) {
        let at_reading: Vec<_> = arrows
            .iter()
            .filter(|(t, ..)| (t - visit.time).abs() < 1e-9)
            .collect();
        assert!(!at_reading.is_empty(), "no arrow at {} s", visit.time);
        let p = visit.state.position;
        let (x, y, z) = (
            p[mtwin::machine::Axis::X],
            p[mtwin::machine::Axis::Y],
            p[mtwin::machine::Axis::Z],
        );
        // vmc3 by hand: the tool tip at (-0.38 + X, -0.205 + Y, 0.10 + Z) from the workpiece
        // origin, which stands at (-X, -Y, 1.0) in the bed frame.
        let tip = [-0.38 + x, -0.205 + y, 0.10 + z];
        let deviation = pose.translation - mtwin::math::Vector::from_array(tip);
        for (_, vector, origin) in at_reading {
            assert!(near(*origin, tip, F32_M), "{origin:?} vs {tip:?}");
            assert!(
                near(*vector, (deviation * m).to_array(), F32_M),
                "{vector:?} vs {deviation:?} × {m}"
            );
        }
        let frame = workpiece
            .iter()
            .rev()
            .find(|(t, _)| *t <= visit.time + 1e-9)
            .unwrap()
            .1;
        assert!(near(frame, [-x, -y, 1.0], F32_M), "{frame:?}");
    }
    // Both errors sit on X, an axis of the workpiece branch: the tool's actual frame is its
    // nominal one, the workpiece's is not.
    let tool = recording.translations(viz::TOOL_NOMINAL);
    let tool_actual = recording.translations(&viz::tool_actual(m));
    let workpiece_actual = recording.translations(&viz::workpiece_actual(m));
    assert_eq!(tool_actual.len(), arrows.len());
    for (t, a) in &tool_actual {
        assert!(tool.iter().any(|(tn, n)| tn == t && n == a), "at {t} s");
    }
    let moved = workpiece_actual
        .iter()
        .filter(|(t, a)| workpiece.iter().any(|(tn, n)| tn == t && n != a))
        .count();
    assert!(
        moved > workpiece_actual.len() / 2,
        "{moved} of {}",
        workpiece_actual.len()
    );
}

#[test]
fn abbe_lesson_shows_the_reading_minus_the_tip_as_offset_times_pitch() {
    // Closed form: the reflector 150 mm above the tip moves h·ΔEBX more than the tip, EBX(x) =
    // −30 + 0.0789474·x µrad (x in mm), zeroed at each run's first reading (X = 10 mm, going
    // up). The laser zeroes on the true position, so each reading carries one draw of its
    // 20 nm noise: 85 nm is over 4σ; the air is exactly compensated.
    let (_, simulation, recording) = record("teach_abbe.toml");
    let run = simulation.laser.as_ref().unwrap();
    let reading = recording.scalars("laser_um/reading");
    let truth = recording.scalars("laser_um/tool_tip_truth");
    assert_eq!((reading.len(), truth.len()), (24, 24));
    for (((_, r), (_, t)), visit) in reading.iter().zip(&truth).zip(&run.visits) {
        let x_mm = visit.state.position[mtwin::machine::Axis::X] * 1e3;
        let abbe_um = 150e-3 * 0.07894736842105263 * (x_mm - 10.0);
        assert!(
            ((r - t) - abbe_um).abs() < 0.085,
            "at {x_mm} mm: {r} − {t} vs {abbe_um}"
        );
    }
    // The 740 mm travel: 8.8 µm of Abbe error, more than the axis's own 3.7 µm.
    let last = run
        .visits
        .iter()
        .position(|v| (v.state.position[mtwin::machine::Axis::X] - 0.75).abs() < 1e-9)
        .unwrap();
    assert!(reading[last].1 - truth[last].1 > 8.0);
    assert!(recording.text(viz::LESSON).contains("The Abbe error"));
}

#[test]
fn squareness_lesson_logs_every_reading_and_the_diagnostic_plots() {
    let (scenario, simulation, recording) = record("teach_squareness_ballbar.toml");
    let table = &simulation.ballbar[0];
    // Every reading on the timeline at its time, in µm.
    let series = recording.scalars("ballbar_xy_um/deviation");
    assert_eq!(series.len(), table.readings.len());
    let mut expected: Vec<(f64, f64)> = table
        .readings
        .iter()
        .map(|r| (r.time.unwrap(), r.deviation * 1e6))
        .collect();
    expected.sort_by(|a, b| a.0.total_cmp(&b.0));
    for ((t, v), (et, ev)) in series.iter().zip(&expected) {
        assert!((t - et).abs() < 1e-9 && (v - ev).abs() < 1e-9);
    }
    let entities = recording.entities();
    for needed in [
        "/lesson",
        "/ballbar_xy/nominal",
        "/ballbar_xy/trace_ccw",
        "/ballbar_xy/trace_cw",
        "/ballbar_xy/diagnostics/squareness/ccw",
        "/ballbar_xy/diagnostics/residual/ccw",
        "/discovery_ballbar_xy/step_0/ccw",
        "/world/machine/table/visual_0",
        "/world/workpiece_nominal/ballbar_xy/bar",
    ] {
        assert!(
            entities.iter().any(|e| e == needed),
            "{needed} missing from {entities:?}"
        );
    }
    // The trace has one point per reading of its sense.
    let strips = rerun::LineStrips2D::descriptor_strips().component;
    let ccw: usize = recording
        .of("ballbar_xy/trace_ccw")
        .flat_map(|c| {
            c.iter_component::<rerun::components::LineStrip2D>(strips)
                .map(|s| s[0].0.len())
                .collect::<Vec<_>>()
        })
        .sum();
    let expected_ccw = table
        .readings
        .iter()
        .filter(|r| r.sense == mtwin::kinds::ballbar::Sense::Ccw)
        .count();
    assert_eq!(ccw, expected_ccw);
    // The machine moves through the whole test: one arrow per frame, at most every 50 ms.
    let circle = &scenario.ballbar_test.as_ref().unwrap().circles[0];
    let arrows = recording.arrows(&viz::tool_tip_error(2000.0));
    assert!(arrows.len() as f64 >= circle.duration() / 0.05);
    // One step per model discovery tried: the base and each accepted effect.
    let steps = entities
        .iter()
        .filter(|e| e.starts_with("/discovery_ballbar_xy/step_") && e.ends_with("/nominal"))
        .count();
    let discovery = mtwin::kinds::ballbar::discover_ballbar(
        table,
        &mtwin::kinds::ballbar::iso230_4::CircularTest {
            plane: circle.plane,
            radius: circle.radius,
            feed: circle.feed,
        },
        |_| {},
    )
    .unwrap();
    assert_eq!(steps, discovery.accepted().len() + 1);
}

#[test]
fn squareness_lesson_draws_the_significant_diagnostics_and_they_are_the_injected_ones() {
    // The lesson injects a squareness (EC0Y) and X lost motion (EXX reversal) and nothing else
    // that a ball-bar diagnostic names (both axes have the same servo); radius and centre are
    // the set-up, drawn in the trace only. The plots must be the diagnostics that pass the
    // report's significance rule, and those must be the injected two.
    use mtwin::kinds::ballbar::iso230_4::{self, CircleData, CircularTest, Term};
    let (scenario, simulation, recording) = record("teach_squareness_ballbar.toml");
    let circle = &scenario.ballbar_test.as_ref().unwrap().circles[0];
    let test = CircularTest {
        plane: circle.plane,
        radius: circle.radius,
        feed: circle.feed,
    };
    let table = &simulation.ballbar[0];
    let data = CircleData::new(table, &test).unwrap();
    let diagnostics = iso230_4::evaluate(table, &test)
        .unwrap()
        .diagnostics
        .unwrap();
    let mut significant: Vec<String> = diagnostics
        .estimates
        .iter()
        .filter(|(t, _)| !matches!(t, Term::Radius | Term::CentreP | Term::CentreQ))
        .filter(|(t, e)| e.value.abs() > data.significance(*t) * e.u)
        .map(|(t, _)| t.name(circle.plane))
        .collect();
    significant.sort();
    let mut drawn: Vec<String> = recording
        .entities()
        .iter()
        .filter_map(|e| e.strip_prefix("/ballbar_xy/diagnostics/"))
        .filter_map(|e| e.strip_suffix("/nominal"))
        .filter(|e| *e != "residual")
        .map(String::from)
        .collect();
    drawn.sort();
    assert_eq!(drawn, significant);
    assert_eq!(drawn, ["backlash_x", "squareness"]);
}

#[test]
fn squareness_arrow_is_an_x_shift_growing_with_y() {
    // EC0Y = −40 µrad: moving +Y also moves the tool by −EC0Y·Y = +40 µrad × Y along X (the
    // angle between +X and +Y under 90°), so at any frame the arrow's x is 40e-6 × Y × 2000
    // plus X's lost motion (±1 µm), y and z are zero. Y is read back from the arrow's origin:
    // tip y = −0.205 + Y.
    let (_, _, recording) = record("teach_squareness_ballbar.toml");
    let arrows = recording.arrows(&viz::tool_tip_error(2000.0));
    assert!(!arrows.is_empty());
    for (_, vector, origin) in &arrows {
        let y = origin[1] as f64 + 0.205;
        let dx_um = vector[0] as f64 / 2000.0 * 1e6;
        let expected = 40e-6 * y * 1e6;
        assert!(
            (dx_um - expected).abs() <= 1.0 + 1e-3,
            "Y {y}: dx {dx_um} µm vs {expected} ± 1"
        );
        assert!(
            vector[1].abs() < 1e-6 && vector[2].abs() < 1e-6,
            "{vector:?}"
        );
    }
}

#[test]
fn warmup_lesson_follows_the_thermal_twin() {
    let (scenario, simulation, recording) = record("teach_warmup.toml");
    let run = simulation.laser.as_ref().unwrap();
    let records = run.thermal.as_ref().unwrap();
    // The sensor and every node at each reading, as the thermal twin computed them.
    let sensor = recording.scalars("temperatures_degc/x_nut");
    assert_eq!(sensor.len(), records.len());
    for ((t, value), record) in sensor.iter().zip(records) {
        assert!((t - record.visit.time).abs() < 1e-9 && (value - record.readings[0]).abs() < 1e-12);
    }
    let setup = scenario.thermal.as_ref().unwrap();
    for (index, node) in setup.thermal.network.nodes().iter().enumerate() {
        let series = recording.scalars(&format!("temperatures_degc/true/{}", node.name));
        assert_eq!(series.len(), records.len());
        assert!(
            series
                .iter()
                .zip(records)
                .all(|((_, v), r)| (v - r.temperatures[index]).abs() < 1e-12)
        );
    }
    // The arrows carry the thermal errors: the actual poses of the thermal twin, × 1000.
    let arrows = recording.arrows(&viz::tool_tip_error(1000.0));
    assert_eq!(arrows.len(), run.poses.len());
    let machine = &scenario.twin.machine;
    for ((_, vector, _), (visit, pose)) in arrows.iter().zip(run.visits.iter().zip(&run.poses)) {
        let nominal = machine
            .workpiece_from_tool(&visit.state.position)
            .translation;
        assert!(near(
            *vector,
            ((pose.translation - nominal) * 1000.0).to_array(),
            F32_M
        ));
    }
    // Colour by thermal state: the cold first run bluer than the warm last one.
    let colours = rerun::LineStrips2D::descriptor_colors().component;
    let colour = |run: &str| {
        recording
            .of(&format!("laser_plot/run_{run}_up"))
            .flat_map(|c| {
                c.iter_component::<rerun::components::Color>(colours)
                    .map(|c| c[0].to_array())
                    .collect::<Vec<_>>()
            })
            .next()
            .unwrap()
    };
    let (cold, warm) = (colour("1"), colour("4"));
    assert!(
        cold[2] > warm[2] && cold[0] < warm[0],
        "{cold:?} vs {warm:?}"
    );
    assert!(recording.rows("discovery_positioning/step_0/zero") == 1);
}

#[test]
fn volumetric_map_arrows_are_the_map_enlarged() {
    let (_, simulation, recording) = record("vmc3_volumetric.toml");
    let map = simulation.volumetric.as_ref().unwrap();
    let vectors = rerun::Arrows3D::descriptor_vectors().component;
    let logged: Vec<[f32; 3]> = recording
        .of("world/workpiece_nominal/volumetric_map_x1000")
        .flat_map(|c| {
            c.iter_component::<rerun::components::Vector3D>(vectors)
                .flat_map(|b| b.iter().map(|v| v.0.0).collect::<Vec<_>>())
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(logged.len(), 9 * 5 * 5);
    for (v, row) in logged.iter().zip(&map.rows) {
        assert!(near(
            *v,
            (row.deviation.translation * 1000.0).to_array(),
            F32_M
        ));
    }
    // The tour: one frame per grid point, its arrow the chain's deviation (the map's model).
    let tour = recording.arrows(&viz::tool_tip_error(1000.0));
    assert_eq!(tour.len(), map.rows.len());
    for ((_, v, _), row) in tour.iter().zip(&map.rows) {
        assert!(near(
            *v,
            (row.deviation.translation * 1000.0).to_array(),
            F32_M
        ));
    }
    let counts: BTreeMap<String, usize> = recording
        .entities()
        .into_iter()
        .map(|e| (e.clone(), recording.rows(&e)))
        .collect();
    assert_eq!(
        counts["/world/machine/table"],
        map.rows.len(),
        "one frame of the table per grid point"
    );
}

#[test]
fn rtest_lesson_logs_each_pose_and_the_circle_an_axis_offset_draws() {
    // EX0C = 20 µm alone, C turning at A = 0: the tool relative to the sphere moves by
    // −EX0C·(1 − cos C, sin C, 0) in machine axes (tests/it/rtest.rs derives it). The nest's
    // noise (0.1 µm per probe, orthonormal axes) and the zeroing at the first pose give each
    // component a standard deviation of √2 · 0.1 µm; 5 of those bound the difference.
    let (_, simulation, recording) = record("teach_rtest.toml");
    let table = simulation.rtest.as_ref().unwrap();
    let (name, rows) = &table.tests()[0];
    assert_eq!(*name, "C circle at A0");
    let series = |axis: &str| recording.scalars(&format!("rtest/C_circle_at_A0/{axis}"));
    let (dx, dy) = (series("dx_um"), series("dy_um"));
    assert_eq!((dx.len(), dy.len()), (73, 73));
    let bound = 5.0 * 2f64.sqrt() * 0.1;
    for ((row, x), y) in rows.iter().zip(&dx).zip(&dy) {
        assert!((x.1 - row.deviation.x * 1e6).abs() < 1e-9);
        let c = row.angle(mtwin::machine::Axis::C).unwrap();
        assert!(
            (x.1 + 20.0 * (1.0 - c.cos())).abs() < bound,
            "C {c}: dx {}",
            x.1
        );
        assert!((y.1 + 20.0 * c.sin()).abs() < bound, "C {c}: dy {}", y.1);
    }
    assert_eq!(
        recording.rows("world/workpiece_nominal/rtest_C_circle_at_A0_x2000"),
        73
    );
    assert!(recording.rows("world/workpiece_nominal/rtest_sphere") > 0);
    assert_eq!(recording.scalars("rtest/A_swing_at_C0/probe3_um").len(), 19);
}

/// One row of an Arrows3D entity: time (s), every vector, every origin.
type ArrowsRow = (f64, Vec<[f32; 3]>, Vec<[f32; 3]>);

/// Every row of an Arrows3D entity, in time order.
fn all_arrows(recording: &Recording, entity: &str) -> Vec<ArrowsRow> {
    let vectors = rerun::Arrows3D::descriptor_vectors().component;
    let origins = rerun::Arrows3D::descriptor_origins().component;
    let mut out = Vec::new();
    for chunk in recording.of(entity) {
        let times = chunk.iter_component_indices(rerun::TimelineName::from(TIMELINE), vectors);
        let v = chunk.iter_component::<rerun::components::Vector3D>(vectors);
        let o = chunk.iter_component::<rerun::components::Position3D>(origins);
        for (((time, _), v), o) in times.zip(v).zip(o) {
            out.push((
                time.as_i64() as f64 * 1e-9,
                v.iter().map(|v| v.0.0).collect(),
                o.iter().map(|o| o.0.0).collect(),
            ));
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

#[test]
fn probe_lesson_logs_every_touch_and_the_fitted_centres_move_as_the_axis_offset_says() {
    // EY0C = 20 µm alone, the sphere probed at C = 0, 90, 180, 270° (A = 0). The table turns by
    // R = Rot(z, −C) (trunnion5's C axis points along −Z) about the line δ = EY0C·ŷ off the
    // nominal one, so the sphere stands (I − R)·δ (bed frame) from where the controller puts it
    // and the fitted centre carries that error; in the workpiece frame, turned by R from the
    // bed, it is Rᵀ·(I − R)·δ = (Rot(z, C) − I)·δ = EY0C·(−sin C, cos C − 1, 0). Exact for an
    // offset (no lever), and the probe's pre-travel is the same in every direction, so only
    // the trigger scatter (σ = 0.25 µm along each approach, i.e. along the normal) moves the
    // fit. Linearised, 5 points (4 at 30° elevation 90° apart, the pole) with a free radius
    // give each horizontal centre component a standard deviation σ/√(2·cos²30°) = 0.82σ and
    // the vertical one √5·σ (the pole against the side points' mean: (JᵀJ)⁻¹ of the z–radius
    // block [[2, 3], [3, 5]] is [[5, −3], [−3, 2]]); 5 of those bound each component.
    use mtwin::kinds::probe::Target;
    use mtwin::math::Vector;
    let (scenario, simulation, recording) = record("teach_probe.toml");
    let test = scenario.probe_test.as_ref().unwrap();
    let run = simulation.probe.as_ref().unwrap();
    let m = scenario.lesson.as_ref().unwrap().magnification;
    assert_eq!(m, 500.0);
    let feature = &test.cycles[0].features;
    let Target::Sphere(sphere) = &feature[0].target else {
        panic!("a sphere cycle")
    };
    let nominal = sphere.centre;
    // A touch per point and position, each drawn at its approach start and its latch.
    assert_eq!(run.probe.touches.len(), 4 * 5);
    assert_eq!(run.spheres.spheres.len(), 4);
    let points = rerun::Points3D::descriptor_positions().component;
    let drawn: Vec<usize> = recording
        .of("world/workpiece_nominal/probe_touches")
        .flat_map(|c| {
            c.iter_component::<rerun::components::Position3D>(points)
                .map(|p| p.len())
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(drawn.len(), 20);
    assert_eq!(drawn.iter().max(), Some(&20));
    assert_eq!(recording.rows("world/machine/rotary_table"), 2 * 20);
    // The residual of each touch from the spheres table's fit.
    let stylus = test.probe.stylus_radius;
    let residuals = recording.scalars("probe/residual_um");
    assert_eq!(residuals.len(), 20);
    for ((_, logged), touch) in residuals.iter().zip(&run.probe.touches) {
        let fit = &run.spheres.spheres[touch.key.feature - 1];
        let expected = ((touch.position - fit.centre).length() - (fit.radius + stylus)) * 1e6;
        assert!((logged - expected).abs() < 1e-9, "{logged} vs {expected}");
        assert!(logged.abs() < 5.0 * 0.25, "{logged} µm");
    }
    // trunnion5 at A = 0 by hand: the tool tip is at (X − 325, Y − 275, Z + 100) mm from the
    // workpiece origin in bed axes, and the workpiece frame is turned by Rot(z, −C).
    let workpiece = |xyz: Vector, c: f64| {
        let bed = xyz + Vector::new(-0.325, -0.275, 0.1);
        Vector::new(
            bed.x * c.cos() - bed.y * c.sin(),
            bed.x * c.sin() + bed.y * c.cos(),
            bed.z,
        )
    };
    let arrows = all_arrows(
        &recording,
        "world/workpiece_nominal/probe_centre_error_x500",
    );
    assert_eq!(arrows.len(), 4);
    let (_, vectors, origins) = arrows.last().unwrap();
    assert_eq!((vectors.len(), origins.len()), (4, 4));
    let sigma = 0.25;
    let (horizontal, vertical) = (
        5.0 * sigma / (2.0 * 30f64.to_radians().cos().powi(2)).sqrt(),
        5.0 * 5f64.sqrt() * sigma,
    );
    let tool = recording.arrows(&viz::tool_tip_error(m));
    assert_eq!(tool.len(), 2 * 20);
    for (((fit, vector), origin), (time, ..)) in run
        .spheres
        .spheres
        .iter()
        .zip(vectors)
        .zip(origins)
        .zip(&arrows)
    {
        let c = fit.key.rotary[2].unwrap();
        assert_eq!(fit.key.rotary[0], Some(0.0));
        let error = workpiece(fit.centre, c) - nominal;
        assert!(near(*origin, nominal.to_array(), F32_M), "{origin:?}");
        assert!(
            near(*vector, (error * m).to_array(), F32_M),
            "C {c}: {vector:?} vs {error:?} × {m}"
        );
        let expected = Vector::new(-c.sin(), c.cos() - 1.0, 0.0) * 20.0;
        let um = error * 1e6;
        assert!(
            (um.x - expected.x).abs() < horizontal
                && (um.y - expected.y).abs() < horizontal
                && (um.z - expected.z).abs() < vertical,
            "C {}°: centre error {um:?} µm vs {expected:?} ± ({horizontal:.2}, {vertical:.2})",
            c.to_degrees()
        );
        // At the fit (the position's last latch) the tool-tip error arrow is the opposite.
        let (_, at_fit, _) = tool.iter().find(|(t, ..)| t == time).unwrap();
        let sum: Vec<f64> = (0..3)
            .map(|i| (vector[i] + at_fit[i]) as f64 / m * 1e6)
            .collect();
        assert!(
            sum[0].abs() < horizontal && sum[1].abs() < horizontal && sum[2].abs() < vertical,
            "C {c}: centre error + tool-tip error = {sum:?} µm"
        );
    }
    let positions = recording.scalars("probe/centre_error_um/dy");
    assert_eq!(positions.len(), 4);
    assert!(
        recording
            .text(viz::LESSON)
            .contains("EY0C·(−sin C, cos C − 1, 0)")
    );
}

/// `(time s, strips)` of every row of a LineStrips2D entity, in time order (static rows first).
type StripsRow = (f64, Vec<Vec<[f32; 2]>>);

fn strips(recording: &Recording, entity: &str) -> Vec<StripsRow> {
    let id = rerun::LineStrips2D::descriptor_strips().component;
    let mut out = Vec::new();
    for chunk in recording.of(entity) {
        let times = chunk.iter_component_indices(rerun::TimelineName::from(TIMELINE), id);
        let rows = chunk.iter_component::<rerun::components::LineStrip2D>(id);
        for ((time, _), row) in times.zip(rows) {
            out.push((
                time.as_i64() as f64 * 1e-9,
                row.iter()
                    .map(|s| s.0.iter().map(|p| p.0).collect())
                    .collect(),
            ));
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// The scale the lesson panel states for a 2D plot: the number in "1 µm drawn as <n> units"
/// after the entity's name in the legend.
fn stated_scale(text: &str, entity: &str) -> f64 {
    let after = &text[text.find(&format!("`{entity}`")).unwrap()..];
    let number = after.split("1 µm drawn as ").nth(1).unwrap();
    number.split(' ').next().unwrap().parse().unwrap()
}

/// A polar plot read back: its centre and base radius from the logged base circle, the scale
/// from the legend, and each point of `strip` as (angle rad, deviation µm).
fn read_polar(recording: &Recording, root: &str, strip: &[[f32; 2]]) -> Vec<(f64, f64)> {
    let nominal = &strips(recording, &format!("{root}/nominal"))[0].1[0];
    let n = nominal.len() - 1; // closed: the last point repeats the first
    let centre = (0..2)
        .map(|k| nominal[..n].iter().map(|p| p[k] as f64).sum::<f64>() / n as f64)
        .collect::<Vec<_>>();
    let radius = ((nominal[0][0] as f64 - centre[0]).powi(2)
        + (nominal[0][1] as f64 - centre[1]).powi(2))
    .sqrt();
    let scale = stated_scale(&recording.text(viz::LESSON), &format!("{root}/synchronous"));
    strip
        .iter()
        .map(|p| {
            // Plot points are drawn with y downward: y upward is minus the logged y.
            let (x, y) = (p[0] as f64 - centre[0], -(p[1] as f64 - centre[1]));
            (
                y.atan2(x).rem_euclid(std::f64::consts::TAU),
                (x.hypot(y) - radius) / scale,
            )
        })
        .collect()
}

mod spindle_lesson;
