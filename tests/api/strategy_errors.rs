//! Error paths of the strategies: bad knobs rejected with typed errors that name the method,
//! the knob (by its symbol: the library knows no command-line flag) and the value, and a
//! singular K failing for the rules that need K⁻¹ but not for `lagrange` or the constant
//! penalty.

use crate::strategy_support::{cond_of, rounding_tol};
use penalty_lab::metrics;
use penalty_lab::strategy::{self, registry, symbol, Knobs, Method};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
use penalty_lab::Error;

#[test]
fn bad_knobs_are_rejected_with_clear_messages() {
    for name in ["spring", "paper", "condensed"] {
        for bad in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            let e = Method::from_name(
                name,
                Knobs {
                    delta: Some(bad),
                    ..Default::default()
                },
            )
            .unwrap_err();
            let msg = e.to_string();
            assert!(e.is_input(), "{name} δ={bad}: {e:?}");
            match &e {
                Error::NotPositive { name: knob, value } => {
                    assert_eq!(knob, symbol::DELTA);
                    assert!(value.to_bits() == bad.to_bits() || value.is_nan() && bad.is_nan());
                }
                other => panic!("{name} δ={bad}: {other:?}"),
            }
            assert!(msg.contains("δ") && msg.contains("> 0"), "{msg}");
            assert!(msg.contains(&format!("{bad}")), "{msg} should quote {bad}");
        }
        let e = Method::from_name(name, Knobs::default()).unwrap_err();
        assert!(
            matches!(&e, Error::MissingKnob { method, knob } if method == name && *knob == symbol::DELTA),
            "{e:?}"
        );
        assert!(
            e.to_string().contains(&format!("method {name} needs δ")),
            "{e}"
        );
    }
    for (name, knobs) in [
        (
            "constant",
            Knobs {
                eps: Some(-1.0),
                ..Default::default()
            },
        ),
        (
            "scaled",
            Knobs {
                factor: Some(0.0),
                ..Default::default()
            },
        ),
        (
            "augmented",
            Knobs {
                eps: Some(1.0),
                tol: Some(f64::NAN),
                ..Default::default()
            },
        ),
    ] {
        assert!(
            matches!(
                Method::from_name(name, knobs),
                Err(Error::NotPositive { .. })
            ),
            "{name}"
        );
    }
    let e = Method::from_name("penalty", Knobs::default()).unwrap_err();
    assert!(
        matches!(&e, Error::Unknown { what: "method", name, .. } if name == "penalty"),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(
        msg.contains("unknown method") && msg.contains("'penalty'"),
        "{msg}"
    );
    for valid in registry::names() {
        assert!(msg.contains(valid), "{msg} should list {valid}");
    }
    // Valid knobs round-trip.
    let m = Method::from_name(
        "condensed",
        Knobs {
            delta: Some(0.1),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(m, Method::condensed(0.1));
}

/// Two unit springs in series with no spring to ground: K = k[[1, −1], [−1, 1]] is singular
/// (rigid translation); a bilateral tie of DOF 0 at û removes it.
fn floating_chain(k: f64, q: [f64; 2], uh: f64) -> Problem {
    Problem::new(
        Stiffness::from_rows(&[vec![k, -k], vec![-k, k]]).unwrap(),
        q.to_vec(),
        vec![Constraint::on_dof(0, uh, ConstraintKind::Bilateral)],
    )
    .unwrap()
}

#[test]
fn singular_k_fails_for_condensed_but_not_for_lagrange_or_constant() {
    let (k, q, uh) = (4.0, [1.5, -0.5], 0.25);
    let p = floating_chain(k, q, uh);
    for m in [Method::condensed(0.1), Method::spring(0.1)] {
        match strategy::solve(&p, m) {
            Err(Error::Singular(msg)) => assert!(msg.contains("K is singular"), "{msg}"),
            other => panic!("{}: expected Error::Singular, got {other:?}", m.name()),
        }
    }
    // Hand solution: row 1 gives k(u1 − u0) = q1; the tie carries the total load,
    // λ = q0 + q1 (K u = q − D λ); lagrange has u0 = û, the penalty u0 = û + λ/ε.
    let lam = q[0] + q[1];
    let sol = strategy::solve(&p, Method::lagrange()).unwrap();
    let cond = cond_of(&metrics::system_matrix(&p, &sol));
    let tol = rounding_tol(cond, 3, 1.0);
    assert!((sol.u[0] - uh).abs() <= tol);
    assert!((sol.u[1] - (uh + q[1] / k)).abs() <= tol);
    assert!((sol.forces[0] - lam).abs() <= tol * k);
    for eps in [10.0, 1e4] {
        let sol = strategy::solve(&p, Method::constant(eps)).unwrap();
        let cond = cond_of(&metrics::system_matrix(&p, &sol));
        let tol = rounding_tol(cond, 2, 1.0);
        let u0 = uh + lam / eps;
        assert!((sol.u[0] - u0).abs() <= tol, "ε={eps}: {}", sol.u[0]);
        assert!((sol.u[1] - (u0 + q[1] / k)).abs() <= tol);
        assert!((sol.forces[0] - lam).abs() <= tol * eps);
    }
}
