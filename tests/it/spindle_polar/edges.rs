//! Bad inputs, a perfectly round profile, pooled revolutions and centre names.

use super::*;

#[test]
fn bad_inputs_are_errors_not_panics() {
    let angles = equal_angles(36);
    let p: Vec<Real> = angles.iter().map(|t| (3.0 * t).cos() * UM).collect();
    let mut nan = p.clone();
    nan[5] = Real::NAN;
    let mut nan_angle = angles.clone();
    nan_angle[7] = Real::NAN;
    for centre in Centre::ALL {
        assert!(matches!(
            polar::fit(&nan, &angles, centre),
            Err(PolarError::NonFinite {
                what: "value",
                index: 5
            })
        ));
        assert!(matches!(
            polar::fit(&p, &nan_angle, centre),
            Err(PolarError::NonFinite {
                what: "angle",
                index: 7
            })
        ));
        assert!(matches!(
            polar::fit(&p[..35], &angles, centre),
            Err(PolarError::LengthMismatch {
                values: 35,
                angles: 36
            })
        ));
        assert!(matches!(
            polar::fit(&p[..2], &angles[..2], centre),
            Err(PolarError::TooFew(2))
        ));
        assert!(matches!(
            polar::fit(&[], &[], centre),
            Err(PolarError::TooFew(0))
        ));
    }
    // Two directions only (0 and π, repeated): no circle is defined beyond PC.
    let two: Vec<Real> = (0..10).map(|i| PI * (i % 2) as Real).collect();
    let q: Vec<Real> = (0..10).map(|i| i as Real * UM).collect();
    assert!(polar::fit(&q, &two, Centre::Pc).is_ok());
    assert!(matches!(
        polar::fit(&q, &two, Centre::Lsc),
        Err(PolarError::TooFewDirections { needed: 3, .. })
    ));
    assert!(matches!(
        polar::fit(&q, &two, Centre::Mrs),
        Err(PolarError::TooFewDirections { needed: 4, .. })
    ));
    assert!(matches!(
        polar::fit(&q, &two, Centre::Mcc),
        Err(PolarError::NotSurrounded { .. })
    ));
    // range_about never fails: NaN in, NaN out.
    let (lo, hi) = polar::range_about(&nan, &angles, [0.0, 0.0]);
    assert!(lo.is_nan() && hi.is_nan());
    let (lo, hi) = polar::range_about(&p, &angles, [Real::NAN, 0.0]);
    assert!(lo.is_nan() && hi.is_nan());
    let (lo, hi) = polar::range_about(&p, &[], [0.0, 0.0]);
    assert!(lo.is_nan() && hi.is_nan());
}

#[test]
fn a_perfectly_round_profile_has_value_zero_about_every_centre() {
    // A constant (or zero) profile is a perfect spindle, not an error: every centre is at the
    // chart centre (any offset adds a 1-UPR residual of range 2|c|) and every value is 0.
    for level in [0.0, 1.5 * UM] {
        let angles = equal_angles(64);
        let p = vec![level; 64];
        for centre in Centre::ALL {
            let f = fit(&p, &angles, centre);
            assert_eq!(f.value(), 0.0, "{centre}");
            assert!(f.offset[0].abs() <= 1e-15 * UM && f.offset[1].abs() <= 1e-15 * UM);
        }
    }
}

#[test]
fn range_about_pools_revolutions_at_the_same_angles() {
    // Revolution r: e cos(θ − φ) + d_r with d = (−0.4, 1.1, 0.3) µm. About the offset
    // e (cos φ, sin φ) every residual is d_r, so the pooled range is (min d, max d).
    let m = 100;
    let angles = equal_angles(m);
    let (e, phi) = (2.0 * UM, 0.7);
    let levels = [-0.4 * UM, 1.1 * UM, 0.3 * UM];
    let values: Vec<Real> = levels
        .iter()
        .flat_map(|d| angles.iter().map(move |t| e * (t - phi).cos() + d))
        .collect();
    let offset = [e * phi.cos(), e * phi.sin()];
    // Cancellation of the 1-UPR term: rounding at 1e-16 of e.
    let table = Angles::new(&angles).expect("angles");
    for (lo, hi) in [
        polar::range_about(&values, &angles, offset),
        table.range_about(&values, offset),
    ] {
        assert!((lo - levels[0]).abs() <= 1e-15 * UM);
        assert!((hi - levels[1]).abs() <= 1e-15 * UM);
    }
}

#[test]
fn centre_names_round_trip() {
    let names = ["PC", "LSC", "MRS", "MIC", "MCC"];
    for (centre, name) in Centre::ALL.into_iter().zip(names) {
        assert_eq!(centre.to_string(), name);
        assert_eq!(name.parse::<Centre>(), Ok(centre));
        assert_eq!(name.to_lowercase().parse::<Centre>(), Ok(centre));
    }
    assert!("MZC".parse::<Centre>().is_err());
}
