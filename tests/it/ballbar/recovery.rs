//! Every diagnostic recovered, alone and all together.

use super::*;

#[test]
fn each_diagnostic_is_recovered_alone_with_small_cross_talk() {
    // One fault at a time through the whole chain (0.1 µm noise): the named diagnostic within
    // 5 % or 0.2 µm; every other diagnostic within 0.2 µm of radial amplitude of what the
    // fault's physics gives it (0, except the loops' second-order scale mismatch, see
    // `loop_scale_mismatch_ppm`). The matrix (rows: injected, columns: reported, µm of radial
    // amplitude) is printed with --nocapture.
    let mut failures = Vec::new();
    println!("cross-talk (µm of radial amplitude): rows injected, columns reported");
    for fault in faults() {
        let diagnostics = diagnose(&twin(&fault.errors), &fault.servo, 1);
        let got = value(&diagnostics, fault.key);
        if (got - fault.truth).abs() > tolerance(fault.key, fault.truth, &fault.servo) {
            failures.push(format!("{}: {got} vs {}", fault.key, fault.truth));
        }
        let mut row = format!("{:>22}", fault.key);
        for key in DIAGNOSTIC_KEYS {
            let radial = value(&diagnostics, key) * radial_per_unit(key);
            row += &format!(" {radial:>6.2}");
            let expected = fault
                .also
                .iter()
                .find(|(k, _)| *k == key)
                .map_or(0.0, |(_, v)| v * radial_per_unit(key));
            if key != fault.key && (radial - expected).abs() > 0.2 {
                failures.push(format!(
                    "{} leaks {radial:.3} µm into {key} (physics: {expected:.3})",
                    fault.key
                ));
            }
        }
        println!("{row}");
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn all_faults_together_are_recovered_over_several_seeds() {
    // Every fault of `faults()` at once (one twin, one servo), three noise seeds.
    let all = faults();
    let mut errors: Vec<(&str, ErrorFunction)> = Vec::new();
    let mut servo = Servo::default();
    for fault in &all {
        for (name, function) in &fault.errors {
            match errors.iter_mut().find(|(n, _)| n == name) {
                Some((_, existing)) => {
                    *existing = ErrorFunction::Sum(vec![existing.clone(), function.clone()])
                }
                None => errors.push((name, function.clone())),
            }
        }
        for axis in 0..3 {
            let (given, default) = (fault.servo.axes[axis], AxisServo::DEFAULT);
            let mine = &mut servo.axes[axis];
            if given.kv != default.kv {
                mine.kv = given.kv;
            }
            if given.spike_height != 0.0 {
                mine.spike_height = given.spike_height;
                mine.spike_decay = given.spike_decay;
            }
        }
    }
    let twin = twin(&errors);
    let mut failures = Vec::new();
    for seed in 1..=3 {
        let diagnostics = diagnose(&twin, &servo, seed);
        for fault in &all {
            let also: Real = all
                .iter()
                .flat_map(|f| &f.also)
                .filter(|(k, _)| *k == fault.key)
                .map(|(_, v)| v)
                .sum();
            let got = value(&diagnostics, fault.key) - also;
            if (got - fault.truth).abs() > tolerance(fault.key, fault.truth, &servo) {
                failures.push(format!(
                    "seed {seed}: {} {got} vs {}",
                    fault.key, fault.truth
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
