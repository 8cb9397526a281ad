//! The line and spectrum charts and a jittering logged speed.

use super::*;

#[test]
fn a_line_chart_puts_points_on_its_axes() {
    // x over [0, 10] (step 2), y over [0, 5] (step 1): (x, y) → (80 + 48x, 370 − 64y).
    let a = [(0.0, 0.0), (10.0, 5.0)];
    let b = [(2.0, 1.0), (8.0, 4.0), (Real::NAN, 1.0)];
    let svg = line_svg(
        "Value against speed",
        "speed (rpm)",
        "value (µm)",
        &[("synchronous", &a), ("asynchronous", &b)],
    );
    let lines = elements(&svg, "polyline");
    assert_eq!(lines.len(), 2);
    assert_eq!(attribute(&lines[0], "points"), "80.0,370.0 560.0,50.0");
    assert_eq!(attribute(&lines[1], "points"), "176.0,306.0 464.0,114.0");
    assert!(svg.contains(">speed (rpm)</text>") && svg.contains(">value (µm)</text>"));
    assert!(
        svg.contains(">10</text>") && svg.contains(">5</text>"),
        "tick labels"
    );
}

#[test]
fn a_spectrum_draws_synchronous_and_asynchronous_bars() {
    // Frequency over [0, 4] (step 1), amplitude over [0, 2] µm (step 0.5):
    // (f, a) → (80 + 120 f, 370 − 160 a).
    let lines = [(1.0, 2.0, true), (2.0, 0.5, true), (3.37, 0.25, false)];
    let svg = spectrum_svg("Spectrum", &lines);
    let bars = elements(&svg, "line");
    let class = |c: &str| {
        bars.iter()
            .filter(|b| b.iter().any(|(k, v)| k == "class" && v == c))
            .collect::<Vec<_>>()
    };
    let (sync, asynchronous) = (class("sync"), class("async"));
    assert_eq!((sync.len(), asynchronous.len()), (2, 1));
    let ends =
        |b: &Vec<(String, String)>| ["x1", "y1", "x2", "y2"].map(|k| attribute(b, k).to_string());
    assert_eq!(ends(sync[0]), ["200.0", "370.0", "200.0", "50.0"]);
    assert_eq!(ends(asynchronous[0]), ["484.4", "370.0", "484.4", "330.0"]);
    assert_ne!(
        attribute(sync[0], "stroke"),
        attribute(asynchronous[0], "stroke")
    );
    assert!(svg.contains(">cycles per revolution (UPR)</text>"));
    assert!(svg.contains(">amplitude (µm)</text>"));
    // Nothing to draw is still a well-formed document.
    assert!(
        elements(&spectrum_svg("Empty", &[]), "line")
            .iter()
            .all(|b| b.iter().all(|(k, _)| k != "class"))
    );
}

#[test]
fn a_logged_measured_speed_that_jitters_reads_as_one_run_at_its_mean() {
    // Two revolutions of 8 samples at 60 rpm, then the same at 120 rpm, as an analyser logs
    // the measured speed: ±0.03 % around each commanded one. Read as two runs, each at the
    // mean of its logged speeds; the clean table (exact speeds) reads the same runs.
    let table = |jitter: &dyn Fn(usize) -> f64| {
        let mut text = String::from("x_um,revolution,angle_deg,speed_rpm\n");
        let mut k = 0;
        for speed in [60.0, 120.0] {
            for revolution in 0..2 {
                for s in 0..8 {
                    let angle = 45.0 * s as f64;
                    text += &format!(
                        "{:.3},{revolution},{angle},{:.4}\n",
                        (angle.to_radians()).cos(),
                        speed * (1.0 + jitter(k))
                    );
                    k += 1;
                }
            }
        }
        parse(text.as_bytes(), "t.csv").unwrap_or_else(|e| panic!("{e}"))
    };
    let clean = table(&|_| 0.0);
    let jittered = table(&|k| 3e-4 * if k % 3 == 0 { 1.0 } else { -0.5 });
    assert_eq!(jittered.record.revolution, clean.record.revolution);
    let rpm = |t: &SpindleTable, i: usize| t.record.speed[i] * 60.0 / (2.0 * PI);
    for i in 0..32 {
        // Within 0.03 % of the commanded speed, one value per run.
        assert!(
            close(rpm(&jittered, i), rpm(&clean, i), 3e-4 * rpm(&clean, i)),
            "{i}"
        );
        assert_eq!(
            jittered.record.speed[i],
            jittered.record.speed[16 * (i / 16)]
        );
    }
    // A step of 2 % is a new run at the next speed, jitter or not.
    let stepped = table(&|k| if (8..16).contains(&k) { 0.02 } else { 0.0 });
    assert_ne!(stepped.record.speed[0], stepped.record.speed[8]);
}
