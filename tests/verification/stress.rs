//! Stability stress: the double-double reference against exact rational
//! arithmetic, what refinement and equilibration provably do, the O(1/ε) penalty error, and
//! every strategy at extreme knobs — no panic, no NaN/Inf, warnings where digits are lost.
//!
//! Expected values come from theory (error-free transformations, exact rationals, the
//! classical forward-error bound cond₂·ε_mach, the O(1/ε) convergence of the penalty
//! solution, power-of-two scaling being exact), never from our own output.

use crate::common;

use num_rational::BigRational;
use num_traits::{ToPrimitive, Zero};
use penalty_lab::generate::Family;
use penalty_lab::metrics::{self, MetricSet};
use penalty_lab::model::beam::paper;
use penalty_lab::strategy::{self, Method};
use penalty_lab::study::stress::{
    self as stability, two_prod, two_sum, Dd, PenalizedSystem, ResidualPrecision, SolveOptions,
    StressConfig, StressScene,
};
use penalty_lab::system::{ConstraintKind, Problem};
use proptest::prelude::*;

const EPS: f64 = f64::EPSILON;

fn rat(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// Exact solution of A x = b by Gaussian elimination over the rationals.
fn exact_solve(a: Vec<Vec<BigRational>>, b: Vec<BigRational>) -> Vec<BigRational> {
    let n = b.len();
    let mut a = a;
    let mut b = b;
    for k in 0..n {
        let p = (k..n).find(|&i| !a[i][k].is_zero()).expect("nonsingular");
        a.swap(k, p);
        b.swap(k, p);
        for i in k + 1..n {
            if a[i][k].is_zero() {
                continue;
            }
            let l = &a[i][k] / &a[k][k];
            let (top, bottom) = a.split_at_mut(i);
            for (aij, akj) in bottom[0][k..].iter_mut().zip(&top[k][k..]) {
                *aij -= &l * akj;
            }
            let t = &l * &b[k];
            b[i] -= t;
        }
    }
    let mut x = vec![BigRational::zero(); n];
    for i in (0..n).rev() {
        let mut s = b[i].clone();
        for j in i + 1..n {
            s -= &a[i][j] * &x[j];
        }
        x[i] = s / &a[i][i];
    }
    x
}

/// The penalized system of `p` with penalties `eps`, solved exactly (rationals → f64).
fn exact_penalized(p: &Problem, eps: &[f64]) -> Vec<f64> {
    let n = p.n();
    let mut a = vec![vec![BigRational::zero(); n]; n];
    p.k.for_each_entry(|i, j, v| a[i][j] += rat(v));
    let mut b: Vec<BigRational> = p.q.iter().map(|&v| rat(v)).collect();
    for (c, &e) in p.constraints.iter().zip(eps) {
        a[c.single_dof().unwrap()][c.single_dof().unwrap()] += rat(e);
        b[c.single_dof().unwrap()] += rat(e) * rat(c.limit);
    }
    exact_solve(a, b)
        .iter()
        .map(|x| x.to_f64().expect("representable"))
        .collect()
}

fn rel(u: &[f64], r: &[f64]) -> f64 {
    metrics::relative_error(u, r)
}

fn paper_scene() -> StressScene {
    StressScene {
        name: "paper-beam".into(),
        family: "paper".into(),
        problem: paper::problem(),
    }
}

fn small_cfg() -> StressConfig {
    StressConfig {
        eps: (0..=23).map(|k| 10f64.powi(k - 3)).collect(),
        ..StressConfig::default()
    }
}

fn stress_scenes() -> Vec<StressScene> {
    stability::stress_scenes(11, 1, &[Family::Beam, Family::Spectrum, Family::Membrane]).unwrap()
}

// ----------------------------------------------------------------------------------------
// Double-double and the reference
// ----------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// two_sum and two_prod are error-free: s + e = a + b and p + e = a·b exactly.
    #[test]
    fn error_free_transformations_are_exact(
        a in -1e100..1e100f64,
        b in -1e100..1e100f64,
        sa in -30i32..30,
    ) {
        let b = b * 2f64.powi(sa);
        let (s, e) = two_sum(a, b);
        prop_assert_eq!(rat(s) + rat(e), rat(a) + rat(b));
        let (p, e) = two_prod(a, b);
        prop_assert_eq!(rat(p) + rat(e), rat(a) * rat(b));
    }

    /// Double-double +, −, ·, / have relative error ≤ 2^-100 against exact rationals.
    #[test]
    fn dd_operations_are_accurate(
        a in (-1e10..1e10f64, -1.0..1.0f64),
        b in (1e-3..1e10f64, -1.0..1.0f64),
    ) {
        let x = Dd::sum(a.0, a.1 * 1e-20);
        let y = Dd::sum(b.0, b.1 * 1e-20);
        let (rx, ry) = (rat(x.hi) + rat(x.lo), rat(y.hi) + rat(y.lo));
        let tol = 2f64.powi(-100);
        for (got, want) in [
            (x + y, &rx + &ry),
            (x - y, &rx - &ry),
            (x * y, &rx * &ry),
            (x / y, &rx / &ry),
        ] {
            let g = rat(got.hi) + rat(got.lo);
            if want.is_zero() {
                prop_assert!(g.is_zero());
            } else {
                let err = ((g - &want) / &want).to_f64().unwrap().abs();
                prop_assert!(err <= tol, "relative error {:e}", err);
            }
        }
    }
}

/// The double-double reference equals the exact rational solution (rounded to f64) on the
/// paper's beam for ε from 1e-3 to 1e20, to within n·cond₂·2⁻¹⁰⁴ plus the final rounding.
#[test]
fn reference_matches_exact_rationals_on_the_paper_beam() {
    let p = paper::problem();
    for eps in [1e-3, 1.0, 1e4, 1e8, 1e12, 1e16, 1e20] {
        let pen = vec![eps; p.m()];
        let sys = PenalizedSystem::new(&p, &pen).unwrap();
        let r = sys.reference().unwrap();
        let exact = exact_penalized(&p, &pen);
        let cond = sys.cond2_extended().unwrap();
        let tol = EPS + 16.0 * p.n() as f64 * cond * 2f64.powi(-104);
        let e = rel(&r.u, &exact);
        assert!(e <= tol, "ε = {eps:e}: reference off by {e:e} > {tol:e}");
        assert!(
            r.correction <= tol,
            "ε = {eps:e}: correction {:e}",
            r.correction
        );
    }
}

/// cond₂ computed through the double-double inverse agrees with the harness's f64 route where
/// that is reliable, and grows ∝ ε as ε → ∞ (λ_max ~ ε, λ_min → the stiffness of K on the
/// unconstrained DOFs), where the f64 route is noise.
#[test]
fn extended_cond_agrees_where_f64_is_reliable_and_scales_with_eps() {
    let p = paper::problem();
    let cond = |eps: f64| {
        let sys = PenalizedSystem::new(&p, &vec![eps; p.m()]).unwrap();
        let f64_route = penalty_lab::conditioning::cond2(&sys.matrix())
            .unwrap()
            .cond2;
        (sys.cond2_extended().unwrap(), f64_route)
    };
    for eps in [1e-2, 1.0, 1e3, 1e6] {
        let (c, c64) = cond(eps);
        let tol = 64.0 * p.n() as f64 * c * EPS;
        assert!((c - c64).abs() / c <= tol, "ε = {eps:e}: {c:e} vs {c64:e}");
    }
    let (c19, _) = cond(1e19);
    let (c20, _) = cond(1e20);
    assert!((c20 / c19 - 10.0).abs() < 1e-6, "{c19:e} → {c20:e}");
}

// ----------------------------------------------------------------------------------------
// Refinement and equilibration
// ----------------------------------------------------------------------------------------

/// On every scene and ε: the plain f64 solve obeys the classical bound
/// ‖x − u*‖/‖u*‖ ≤ c·n·cond₂·ε_mach; refinement with an extended residual reaches the
/// correctly rounded solution (error ≤ ε_mach) whenever cond₂·ε_mach ≤ 1e-3; one working-
/// precision refinement leaves a normwise backward error of order n·ε_mach.
#[test]
fn refinement_obeys_theory_on_all_stress_scenes() {
    let mut scenes = vec![paper_scene()];
    scenes.extend(stress_scenes());
    let cfg = small_cfg();
    let mut checked_plain = 0;
    let mut checked_refined = 0;
    for sc in &scenes {
        let rows = stability::eps_study(sc, &cfg).unwrap();
        let n = sc.problem.n() as f64;
        for r in &rows {
            let Some(cond) = r.cond2 else { continue };
            if let Some(e) = r.forward.plain {
                let bound = 4.0 * n * cond * EPS;
                assert!(
                    e <= bound.max(EPS),
                    "{} ε = {:e}: plain error {e:e} > {bound:e}",
                    sc.name,
                    r.eps
                );
                checked_plain += 1;
            }
            if cond * EPS <= 1e-3 {
                let e = r
                    .forward
                    .refined_extended
                    .expect("refinement runs when the plain solve does");
                assert!(
                    e <= EPS,
                    "{} ε = {:e}: refined error {e:e} (cond {cond:e})",
                    sc.name,
                    r.eps
                );
                checked_refined += 1;
            }
        }
        // Backward error after working-precision refinement at a moderate ε.
        let p = &sc.problem;
        let active = stability::exact_contact(p)
            .map(|(_, a)| a)
            .unwrap_or_else(|_| vec![true; p.m()]);
        let pen: Vec<f64> = active.iter().map(|&a| if a { 1e3 } else { 0.0 }).collect();
        let sys = PenalizedSystem::new(p, &pen).unwrap();
        let opts = SolveOptions {
            equilibrate: false,
            refine: Some(ResidualPrecision::Working),
            max_steps: 3,
        };
        let s = stability::solve(&sys, opts).unwrap();
        let last = *s.backward_errors.last().unwrap();
        assert!(
            last <= 4.0 * n * EPS,
            "{}: backward error {last:e}",
            sc.name
        );
    }
    assert!(checked_plain > 100 && checked_refined > 50);
}

/// Power-of-two scaling is exact and Cholesky commutes with it: where both succeed, the
/// equilibrated solution is the plain one bit for bit (van der Sluis). Where the plain
/// factorization is refused as singular to working precision (ε ≥ 1e17 on the beam), the
/// equilibrated one solves, with the error bound of the scaled matrix.
#[test]
fn equilibration_is_exact_and_rescues_refused_factorizations() {
    let p = paper::problem();
    let n = p.n() as f64;
    let mut rescued = 0;
    for k in -3..=20 {
        let eps = 10f64.powi(k);
        let sys = PenalizedSystem::new(&p, &vec![eps; p.m()]).unwrap();
        let eq = SolveOptions {
            equilibrate: true,
            refine: None,
            max_steps: 0,
        };
        let e = stability::solve(&sys, eq).expect("equilibrated solve");
        match stability::solve(&sys, SolveOptions::PLAIN) {
            Ok(plain) => {
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&plain.x), bits(&e.x), "ε = {eps:e}");
            }
            Err(err) => {
                assert!(err.to_string().contains("singular"), "{err}");
                let a = sys.matrix();
                let scaled = a.scaled(&a.equilibration());
                let c = penalty_lab::conditioning::cond2(&scaled).unwrap().cond2;
                let ue = sys.reference().unwrap().u;
                let err = rel(&e.x, &ue);
                // The scaled matrix is well conditioned; the bound is that of the
                // scaled problem (componentwise in the scaled norm: allow a factor n).
                assert!(c < 1e6, "ε = {eps:e}: cond of the scaled matrix {c:e}");
                assert!(err <= 4.0 * n * n * c * EPS, "ε = {eps:e}: {err:e}");
                rescued += 1;
            }
        }
    }
    assert!(
        rescued >= 3,
        "the plain factorization should be refused at ε ≥ 1e17"
    );
}

/// cond₂ of the equilibrated matrix stays bounded as ε → ∞ (S A S tends to a fixed matrix:
/// unit diagonal at the penalized DOFs, their couplings scaled by ε^(-1/2) → 0), while cond₂
/// itself grows ∝ ε.
#[test]
fn equilibrated_cond_is_bounded_as_eps_grows() {
    let sc = paper_scene();
    let cfg = StressConfig {
        eps: vec![1e10, 1e15, 1e20],
        ..StressConfig::default()
    };
    let rows = stability::eps_study(&sc, &cfg).unwrap();
    let s: Vec<f64> = rows.iter().map(|r| r.cond2_scaled.unwrap()).collect();
    let c: Vec<f64> = rows.iter().map(|r| r.cond2.unwrap()).collect();
    assert!(s[2] / s[0] < 2.0 && s[0] / s[2] < 2.0, "{s:?}");
    assert!(c[2] / c[0] > 1e9, "{c:?}");
}

/// The penalty's model error against the exact contact solution decays like 1/ε:
/// u_ε − u* = O(1/ε) (a Neumann series in (εS)⁻¹), so one decade of ε buys one decade.
#[test]
fn penalty_error_decays_like_one_over_eps() {
    let sc = paper_scene();
    let cfg = StressConfig {
        eps: (4..=9).map(|k| 10f64.powi(k)).collect(),
        ..StressConfig::default()
    };
    let rows = stability::eps_study(&sc, &cfg).unwrap();
    for w in rows.windows(2) {
        let (a, b) = (w[0].penalty_error.unwrap(), w[1].penalty_error.unwrap());
        let ratio = b / a;
        assert!(
            (0.09..=0.11).contains(&ratio),
            "ε {:e} → {:e}: error {a:e} → {b:e}",
            w[0].eps,
            w[1].eps
        );
    }
}

// ----------------------------------------------------------------------------------------
// Strategies at the extremes
// ----------------------------------------------------------------------------------------

/// Every strategy at extreme knobs on the paper's beam and generated scenes: no panic; Ok
/// results are finite; errors are one clean line; every system with cond₂·ε_mach > 1e-6
/// carries a warning (including `condensed` with δ below the rounding level of u, see
/// `condensed_with_delta_below_rounding_gives_finite_penalties`).
#[test]
fn strategies_at_extreme_knobs_are_finite_or_clean_errors() {
    let mut scenes = vec![
        paper_scene(),
        StressScene {
            name: "paper-beam-upper".into(),
            family: "paper".into(),
            problem: paper::problem_with_kind(ConstraintKind::Upper),
        },
    ];
    scenes.extend(stress_scenes());
    let cfg = StressConfig::default();
    let mut errors = 0;
    let mut warned = 0;
    for sc in &scenes {
        for r in stability::strategy_study(sc, &cfg).unwrap() {
            let what = format!("{} {} {}={:e}", r.scene, r.method, r.knob, r.value);
            assert_ne!(r.status, "panic", "{what}: {}", r.message);
            assert_ne!(r.status, "non_finite", "{what}: {}", r.message);
            if r.status == "error" {
                assert!(!r.message.is_empty() && !r.message.contains('\n'), "{what}");
                errors += 1;
                continue;
            }
            assert!(r.max_penetration.is_some(), "{what}");
            if r.precision_expected {
                assert!(!r.warnings.is_empty(), "{what}: digits lost but no warning");
                warned += 1;
            }
        }
    }
    // The extremes are really reached: refused factorizations and precision warnings occur.
    assert!(errors > 0 && warned > 0, "errors {errors}, warned {warned}");
}

/// The precision warning fires at an absurd ε on the paper's beam and not at a sane one.
#[test]
fn precision_warning_at_absurd_eps() {
    let p = paper::problem();
    let w = |eps: f64| {
        let s = strategy::solve(&p, Method::constant(eps)).unwrap();
        let m = metrics::compute(&p, &s, MetricSet::ALL).unwrap();
        let mut w = s.warnings.clone();
        w.extend(metrics::precision_warnings(&m));
        w
    };
    assert!(w(1.0).is_empty());
    let big = w(1e14);
    assert!(
        big.iter().any(|m| m.contains("cond2")),
        "no precision warning at ε = 1e14: {big:?}"
    );
}

/// Regression: `condensed` with δ below the rounding level of u returned an infinite penalty —
/// the targeted gap g* = ±δ rounds to 0 in the recomputed `g0 − S r`, and `ε = r / g` divided
/// by it (`solve scenes/paper_beam.scene.json --method condensed --delta
/// 5.1428571428570526e-17` printed a null force and exited 0). ε is now `r / g*`.
#[test]
fn condensed_with_delta_below_rounding_gives_finite_penalties() {
    let p = paper::problem();
    match strategy::solve(&p, Method::condensed(5.142_857_142_857_052_6e-17)) {
        Ok(s) => assert!(
            stability::non_finite_field(&s).is_none(),
            "non-finite output: penalties {:?}, forces {:?}",
            s.penalties,
            s.forces
        ),
        Err(e) => assert!(!e.to_string().contains('\n')),
    }
}

fn scene_pool() -> Vec<Problem> {
    let mut v = vec![
        paper::problem(),
        paper::problem_with_kind(ConstraintKind::Upper),
        paper::problem_with_kind(ConstraintKind::Lower),
    ];
    v.extend(stress_scenes().into_iter().map(|s| s.problem));
    v
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(160))]

    /// Random strategy, random extreme knob (log-uniform over many decades), random scene:
    /// either Ok with finite outputs, or a clean one-line Err; never a panic.
    #[test]
    fn random_extreme_knobs_never_give_nan_or_panic(
        scene in 0usize..6,
        method in 0usize..7,
        k1 in -20.0..22.0f64,
        k2 in -18.0..2.0f64,
        adaptive in any::<bool>(),
    ) {
        let pool = scene_pool();
        let p = &pool[scene % pool.len()];
        let scale = strategy::Prepared::new(p)
            .map(|pr| p.displacement_scale(pr.u0()))
            .unwrap_or(1.0);
        let kmax = p.constraints.iter().map(|c| p.k.diag(c.single_dof().unwrap()).abs()).fold(1e-300, f64::max);
        let x = 10f64.powf(k1);
        let m = match method {
            0 => Method::constant(x),
            1 => Method::scaled(x),
            2 => Method::spring(x * 1e-2 * scale),
            3 => Method::paper(x * 1e-2 * scale),
            4 => Method::condensed(x * 1e-2 * scale),
            5 => Method::lagrange(),
            _ => Method::augmented(kmax * 10f64.powf(k1 / 2.0), scale * 10f64.powf(k2), adaptive),
        };
        let (outcome, sol) = stability::guarded_solve(p, m);
        match outcome {
            stability::Outcome::Ok => {
                let s = sol.unwrap();
                prop_assert!(s.max_penetration >= 0.0);
            }
            stability::Outcome::Error { message } => {
                prop_assert!(!message.is_empty() && !message.contains('\n'), "{}", message);
            }
            other => prop_assert!(false, "{:?} with {:?}", other, m),
        }
    }
}

// ----------------------------------------------------------------------------------------
// The `stress` binary
// ----------------------------------------------------------------------------------------

fn stress_bin() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_stress"))
}

/// `stress --json` on the paper's beam: one JSON object with the manifest (git commit,
/// config, seed), the ε study and the strategy runs; CSV + JSON + PNG/SVG written; no panic
/// and no non-finite output.
#[test]
fn stress_cli_writes_csv_json_and_figures() {
    let tmp = common::tmp_dir("stress-cli");
    let out = tmp.path().join("out");
    let o = common::run_ok(
        stress_bin()
            .args([
                "--families",
                "none",
                "--eps",
                "1e-3:1e20:8",
                "--json",
                "--out",
            ])
            .arg(&out),
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
    let man = &v["manifest"];
    assert!(man["git_commit"].is_string());
    assert_eq!(man["seed"], 7);
    assert_eq!(man["config"]["eps"].as_array().unwrap().len(), 8);
    assert_eq!(man["summary"]["panics"], 0);
    assert_eq!(man["summary"]["non_finite"], 0);
    let rows = v["eps_study"].as_array().unwrap();
    assert_eq!(rows.len(), 2 * 8, "two paper-beam scenes × 8 ε");
    for r in rows {
        // Every ε gets a reference and the best variant solves it.
        assert!(
            r["forward"]["equilibrated_refined_extended"].is_number(),
            "{r}"
        );
        assert!(r["cond2"].as_f64().unwrap() >= 1.0);
    }
    assert!(!v["strategies"].as_array().unwrap().is_empty());
    for f in [
        "eps_study.csv",
        "eps_study.json",
        "strategies.csv",
        "stress.json",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("eps_study.json")).unwrap())
            .unwrap();
    assert_eq!(
        saved, v["eps_study"],
        "eps_study.json holds exactly the rows printed"
    );
    for stem in [
        "forward_error_vs_eps",
        "error_vs_lagrange",
        "forward_error_vs_cond",
    ] {
        for ext in ["png", "svg"] {
            let p = out.join("figures").join(format!("{stem}.{ext}"));
            assert!(p.exists(), "{}", p.display());
        }
    }
    // --render-only redraws the figures from eps_study.json alone.
    common::assert_render_only(
        env!("CARGO_BIN_EXE_stress"),
        &out,
        "figures/forward_error_vs_cond.png",
        "eps_study.json",
        &[],
    );
}

#[test]
fn stress_cli_bad_input_exits_2() {
    let cases = [
        vec!["--eps", "1:0:3"],
        vec!["--eps", "x"],
        vec!["--families", "plate"],
        vec!["--count", "1000"],
        vec!["--eps", "1:10:100000000"],
        vec!["--families", ""],
        vec!["--families", "none,beam"],
        vec!["--families", "beam,beam"],
        vec!["--families", "beam", "--count", "0"],
    ];
    let runs = common::assert_bad_input_writes_nothing(env!("CARGO_BIN_EXE_stress"), &cases, &[]);
    for (args, o) in cases.iter().zip(&runs) {
        let err = common::stderr(o);
        assert!(err.starts_with("error"), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    }
}
