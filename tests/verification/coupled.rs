//! Constraint rows that couple DOFs, against references from outside this
//! project's code: `tests/data/coupled/`, made by `scripts/coupled_reference.py` (NumPy only):
//! three scenes — a truss against a plane inclined by 15°, 30° and 45° (two-term rows), two
//! trusses with non-matching node-to-segment rows (three and six terms, K as Matrix Market),
//! and mortar-like rows that share DOFs beside a coupled bilateral tie, a lower row and
//! single-DOF rows.
//!
//! - `lagrange`: u against the KKT point NumPy finds by enumerating the active sets; cond₂ of
//!   the saddle-point matrix against NumPy's SVD within the accuracy contract;
//! - `constant` and `scaled`: u against the minimizer of the penalized energy found by
//!   enumerating the penalized sets, cond₂(K + D E Dᵀ) against NumPy's SVD;
//! - `condensed`: u against the box QP at ±δ solved the same way, every penetration ≤ δ;
//! - `spring`, `paper`, `augmented`, `barrier`, `optimal` (no closed form): u against a dense nalgebra
//!   solve of the penalized system `(K + D E Dᵀ) u = q + D E û` assembled here from the rows
//!   with the penalties the rule reported (the augmented Lagrangian's shifted limits are its
//!   forces: `ε g = f` there), and cond₂ against nalgebra's SVD with the proven bracket holding;
//! - `optimal`: also feasible (every penetration ≤ δ) and never above `condensed`'s cond₂.
//!
//! u agrees to 1e-8 relative (the references are exact to rounding: cond₂ ≤ 1e6 here, so
//! the agreement is ≈ 1e-10 or better).

use nalgebra::{DMatrix, DVector};
use penalty_lab::scene::read_scene;
use penalty_lab::strategy::{registry, Knobs};
use penalty_lab::study::solve::{solve_scene, SolveOptions};
use penalty_lab::system::{ConstraintKind, Problem};
use serde::Deserialize;
use serde_json::Value;
use std::path::Path;

#[derive(Deserialize)]
struct Reference {
    scenes: Vec<SceneRef>,
}

#[derive(Deserialize)]
struct SceneRef {
    scene: String,
    lagrange: Exact,
    constant: Vec<AtEps>,
    scaled: Vec<AtFactor>,
    condensed: Vec<AtDelta>,
}

#[derive(Deserialize)]
struct Exact {
    u: Vec<f64>,
    active: Vec<usize>,
    cond2: f64,
}

#[derive(Deserialize)]
struct AtEps {
    eps: f64,
    u: Vec<f64>,
    cond2: f64,
}

#[derive(Deserialize)]
struct AtFactor {
    factor: f64,
    u: Vec<f64>,
    cond2: f64,
}

#[derive(Deserialize)]
struct AtDelta {
    delta: f64,
    u: Vec<f64>,
}

const U_TOL: f64 = 1e-8;

fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// cond₂ within the accuracy contract of a dense SVD (ours and the reference's allowance).
fn cond_agrees(ours: f64, reference: f64) -> bool {
    let allowance = 2.0 * 1e-12f64.max(4.0 * f64::EPSILON * reference);
    (ours - reference).abs() <= allowance * reference
}

fn solve(path: &Path, method: &str, knobs: Knobs) -> Value {
    solve_scene(
        path,
        registry::lookup(method).unwrap(),
        knobs,
        &SolveOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{} {method}: {e}", path.display()))
}

/// D as a dense N×m nalgebra matrix, from the rows as stored.
fn d_matrix(p: &Problem) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(p.n(), p.m());
    for (c, con) in p.constraints.iter().enumerate() {
        for &(j, a) in &con.terms {
            d[(j, c)] = a;
        }
    }
    d
}

/// The penalized system `(K + D E Dᵀ) u = q + D E ℓ` assembled densely by matrix products,
/// ℓ_c = d_cᵀu − f_c/ε_c where a force is given (augmented), else û_c.
fn dense_penalized(p: &Problem, eps: &[f64], limits: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let d = d_matrix(p);
    let e = DMatrix::from_diagonal(&DVector::from_column_slice(eps));
    let a = p.k.to_nalgebra() + &d * &e * d.transpose();
    let b = DVector::from_column_slice(&p.q) + &d * (&e * DVector::from_column_slice(limits));
    (a, b)
}

fn svd_cond(a: &DMatrix<f64>) -> f64 {
    let s = a.clone().svd(false, false).singular_values;
    s.max() / s.min()
}

#[test]
fn coupled_rows_agree_with_numpy_and_dense_references() {
    let dir = super::cond_reference::data_dir("coupled");
    let text = std::fs::read_to_string(dir.join("reference.json")).unwrap();
    let reference: Reference = serde_json::from_str(&text).unwrap();
    assert_eq!(reference.scenes.len(), 3);
    let mut failures = Vec::new();
    let mut check_u = |what: &str, out: &Value, u_ref: &[f64]| {
        let err = rel_err(&floats(&out["u"]), u_ref);
        if err.is_nan() || err > U_TOL {
            failures.push(format!("{what}: u differs by {err:e} relative"));
        }
    };
    let mut cond_failures = Vec::new();
    let mut check_cond = |what: &str, out: &Value, c_ref: f64| {
        let c = out["cond2_system"].as_f64().unwrap();
        let (lo, hi) = (
            out["cond2_system_lo"].as_f64().unwrap(),
            out["cond2_system_hi"].as_f64().unwrap(),
        );
        // The reference's own uncertainty: a dense SVD's σ_min to ≈ ε·σ_max.
        let margin = 1e-12f64.max(4.0 * f64::EPSILON * c_ref) * c_ref;
        if !cond_agrees(c, c_ref) || lo > c_ref + margin || hi < c_ref - margin {
            cond_failures.push(format!("{what}: cond2 {c} [{lo}, {hi}] vs {c_ref}"));
        }
    };
    for s in &reference.scenes {
        let path = dir.join(&s.scene);
        let p = read_scene(&path).unwrap().problem;
        assert!(
            p.constraints.iter().any(|c| c.terms.len() > 1),
            "{}: coupled rows",
            s.scene
        );
        let out = solve(&path, "lagrange", Knobs::NONE);
        check_u(&format!("{} lagrange", s.scene), &out, &s.lagrange.u);
        check_cond(&format!("{} lagrange", s.scene), &out, s.lagrange.cond2);
        let active: Vec<usize> = out["system"]["saddle_point"]["active"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_u64().unwrap() as usize)
            .collect();
        assert_eq!(active, s.lagrange.active, "{}: the active set", s.scene);
        for r in &s.constant {
            let out = solve(&path, "constant", Knobs::eps(r.eps));
            let what = format!("{} constant ε = {}", s.scene, r.eps);
            check_u(&what, &out, &r.u);
            check_cond(&what, &out, r.cond2);
        }
        for r in &s.scaled {
            let out = solve(&path, "scaled", Knobs::factor(r.factor));
            let what = format!("{} scaled f = {}", s.scene, r.factor);
            check_u(&what, &out, &r.u);
            check_cond(&what, &out, r.cond2);
        }
        for r in &s.condensed {
            let out = solve(&path, "condensed", Knobs::delta(r.delta));
            check_u(
                &format!("{} condensed δ = {}", s.scene, r.delta),
                &out,
                &r.u,
            );
            let u = floats(&out["u"]);
            for (c, con) in p.constraints.iter().enumerate() {
                let pen = con.kind.penetration(con.gap(&u));
                assert!(
                    pen <= r.delta,
                    "{} condensed: row {c} penetrates {pen}",
                    s.scene
                );
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(cond_failures.is_empty(), "{}", cond_failures.join("\n"));
}

#[test]
fn rules_without_a_closed_form_solve_the_system_they_report() {
    let dir = super::cond_reference::data_dir("coupled");
    let text = std::fs::read_to_string(dir.join("reference.json")).unwrap();
    let reference: Reference = serde_json::from_str(&text).unwrap();
    for s in &reference.scenes {
        let path = dir.join(&s.scene);
        let p = read_scene(&path).unwrap().problem;
        let delta = s.condensed[0].delta;
        let bilateral = p
            .constraints
            .iter()
            .any(|c| c.kind == ConstraintKind::Bilateral);
        let mut cases = vec![
            ("spring", Knobs::delta(delta)),
            ("paper", Knobs::delta(delta)),
            ("augmented", Knobs::eps(s.constant[1].eps)),
        ];
        if !bilateral {
            cases.push(("barrier", Knobs::delta(delta)));
        }
        cases.push(("optimal", Knobs::delta(delta)));
        for (method, knobs) in cases {
            let what = format!("{} {method}", s.scene);
            let out = solve(&path, method, knobs);
            let u = floats(&out["u"]);
            let eps = floats(&out["penalties"]);
            let forces = floats(&out["forces"]);
            // ℓ_c: û_c for the pure penalties; for the augmented Lagrangian and the barrier the
            // ℓ_c with ε_c(d_cᵀu − ℓ_c) = f_c (the shifted limit, the linearization point),
            // so that their check is the equilibrium K u + D f = q.
            let limits: Vec<f64> = p
                .constraints
                .iter()
                .enumerate()
                .map(|(c, con)| match method {
                    "augmented" | "barrier" if eps[c] != 0.0 => con.value(&u) - forces[c] / eps[c],
                    _ => con.limit,
                })
                .collect();
            let (a, b) = dense_penalized(&p, &eps, &limits);
            let u_ref = a.clone().lu().solve(&b).unwrap();
            let err = rel_err(&u, u_ref.as_slice());
            assert!(err <= U_TOL, "{what}: u differs from nalgebra by {err:e}");
            let c_ref = svd_cond(&a);
            let c = out["cond2_system"].as_f64().unwrap();
            // nalgebra's SVD: σ_min to ≈ n·ε·σ_max, so cond₂ to n·ε·cond₂ relative.
            let tol = p.n() as f64 * f64::EPSILON * c_ref * c_ref;
            assert!(
                (c - c_ref).abs() <= tol,
                "{what}: cond2 {c} vs nalgebra {c_ref}"
            );
            assert!(out["cond2_bounds_proven"].as_bool().unwrap(), "{what}");
            let (lo, hi) = (
                out["cond2_system_lo"].as_f64().unwrap(),
                out["cond2_system_hi"].as_f64().unwrap(),
            );
            assert!(
                lo <= c_ref + tol && c_ref - tol <= hi,
                "{what}: [{lo}, {hi}] vs {c_ref}"
            );
        }
        // `optimal` on coupled rows: feasible (every penetration ≤ δ) and never worse than
        // `condensed`, one of its candidates; its u and cond₂ were checked above.
        let opt = solve(&path, "optimal", Knobs::delta(delta));
        let cond = solve(&path, "condensed", Knobs::delta(delta));
        let pen = opt["max_penetration"].as_f64().unwrap();
        assert!(
            pen <= delta * (1.0 + 1e-12),
            "{}: optimal {pen} > δ",
            s.scene
        );
        let (co, cc) = (
            opt["cond2_system"].as_f64().unwrap(),
            cond["cond2_system"].as_f64().unwrap(),
        );
        assert!(
            co <= cc * (1.0 + 1e-9),
            "{}: optimal {co} > condensed {cc}",
            s.scene
        );
    }
}

/// The flat punch turned onto a plane inclined by θ (`model::inclined`): rows n·u ≤ û with
/// n = (−sin θ, cos θ). The exact pressure is the flat punch's, uniform `E*·w/H` (frictionless
/// base, plane strain, reproduced exactly by bilinear elements); Lagrange gives it and
/// `condensed` gives the uniform `E*·(w − δ)/H` with every penetration ≤ δ, to 1e-8 relative.
#[test]
fn inclined_plane_pressure_is_uniform_for_lagrange_and_condensed() {
    use penalty_lab::model::elasticity::{Grid, Material};
    use penalty_lab::model::inclined::inclined_punch;
    use penalty_lab::strategy::{self, Method};
    let grid = Grid::uniform(1.0, 0.5, 7, 5);
    let mat = Material {
        young: 210e3,
        poisson: 0.3,
    };
    let e_star = mat.young / (1.0 - mat.poisson * mat.poisson);
    let (lift, height) = (1e-3, 0.5);
    for theta_deg in [15.0f64, 30.0, 45.0] {
        let ind = inclined_punch(&grid, &mat, lift, theta_deg.to_radians()).unwrap();
        let p = &ind.problem;
        // Two terms per row, but on the symmetry line (one free DOF, in the block's frame).
        let coupled = p.constraints.iter().filter(|c| c.terms.len() == 2).count();
        assert_eq!(coupled, p.m() - 1, "two-term rows");
        assert!(p.k.is_symmetric(), "T K Tᵀ symmetric bit for bit");
        let delta = 1e-2 * lift;
        for (method, expected) in [
            (Method::lagrange(), e_star * lift / height),
            (Method::condensed(delta), e_star * (lift - delta) / height),
        ] {
            let what = format!("θ = {theta_deg}°, {}", method.name());
            let sol = strategy::solve(p, method).unwrap();
            let worst = ind
                .pressures(&sol.u)
                .iter()
                .map(|pc| (pc - expected).abs() / expected)
                .fold(0.0f64, f64::max);
            assert!(worst <= 1e-8, "{what}: pressure off uniform by {worst:e}");
            let pen = p.max_penetration(&sol.u);
            assert!(pen <= delta, "{what}: penetration {pen} > δ = {delta}");
        }
    }
}
