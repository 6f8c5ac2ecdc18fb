//! The accuracy contract of cond₂ on a fixed panel of stored matrices, against references from
//! outside this project's code (`tests/data/cond_reference/`, made by
//! `scripts/cond_panel.py`: python-flint ball arithmetic, mpmath at 40 digits where Arb cannot
//! isolate clustered eigenvalues).
//!
//! Contract (`conditioning` module docs): the reported cond₂ within
//! `max(1e-12, 4·ε_mach·cond₂)` relative of the exact value of the stored matrix, and
//! `cond2_lo ≤ exact ≤ cond2_hi`. The panel holds beams and membranes of 15–225 unknowns,
//! K alone and penalized with ε = 1, 1e6, 1e11 and ε_c = K_dd (graded matrices up to
//! cond₂ ≈ 3e13), dense and sparse routes, and four saddle points `[K D; Dᵀ 0]`: a beam, a
//! membrane and two elasticity scenes (Q4 and P1 tetrahedra from scikit-fem, 320 and 527
//! unknowns) whose negative eigenvalues cluster within 0.1 %.

use penalty_lab::conditioning::{self, saddle, CondReport};
use penalty_lab::scene::matrix_market::read_matrix_market;
use penalty_lab::system::Stiffness;
use serde::Deserialize;
use std::path::Path;

/// A committed panel (`panel.json`): this one's and the adversarial one's.
#[derive(Deserialize)]
pub(crate) struct Panel {
    pub(crate) cases: Vec<Case>,
}

/// One matrix of a panel and its references (decimal strings).
#[derive(Deserialize)]
pub(crate) struct Case {
    pub(crate) case: String,
    /// The adversarial panel's class (near-symmetric, near-double, …).
    #[serde(default)]
    pub(crate) class: String,
    pub(crate) matrix: String,
    #[serde(default)]
    pub(crate) saddle_dofs: Option<Vec<usize>>,
    pub(crate) engine: String,
    pub(crate) sigma_max: String,
    pub(crate) sigma_min: String,
    pub(crate) cond2: String,
}

fn dir() -> std::path::PathBuf {
    data_dir("cond_reference")
}

/// `tests/data/<name>`: a committed panel's folder.
pub(crate) fn data_dir(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The `panel.json` of a committed panel's folder.
pub(crate) fn read_panel<T: serde::de::DeserializeOwned>(dir: &Path) -> T {
    let text = std::fs::read_to_string(dir.join("panel.json")).expect("panel.json");
    serde_json::from_str(&text).expect("panel.json parses")
}

fn panel() -> Panel {
    read_panel(&dir())
}

/// The reference as the f64 nearest to its decimal digits: within u relative of the exact
/// value, so containment is checked with one unit of slack on each side.
/// σ_max and σ_min of the report `r` each within `tol` of their references (decimal
/// strings); a line per miss in `failures`.
pub(crate) fn check_extremes(
    name: &str,
    r: &CondReport,
    sigma_max: &str,
    sigma_min: &str,
    tol: f64,
    failures: &mut Vec<String>,
) {
    for (what, got, want) in [
        ("σ_max", r.sigma_max, reference(sigma_max)),
        ("σ_min", r.sigma_min, reference(sigma_min)),
    ] {
        let e = (got / want - 1.0).abs();
        if e > tol {
            failures.push(format!("{name}: {what} error {e:e} > {tol:e}"));
        }
    }
}

pub(crate) fn reference(s: &str) -> f64 {
    s.trim().parse::<f64>().expect("a decimal number")
}

fn report(case: &Case) -> CondReport {
    let k = read_matrix_market(&dir().join(&case.matrix)).expect("matrix reads");
    match &case.saddle_dofs {
        Some(dofs) => {
            let Stiffness::Sparse(m) = k.clone().in_preferred_storage() else {
                panic!("{}: the saddle cases have a sparse K", case.case)
            };
            saddle::cond2_saddle(&m, dofs).expect("saddle cond₂")
        }
        None => conditioning::cond2(&k).expect("cond₂"),
    }
}

#[test]
fn every_cond2_meets_the_contract_and_every_bound_holds() {
    let panel = panel();
    assert!(panel.cases.len() >= 10, "the panel is complete");
    let u = f64::EPSILON / 2.0;
    let mut failures = Vec::new();
    for case in &panel.cases {
        let r = report(case);
        let exact = reference(&case.cond2);
        let tol = (4.0 * f64::EPSILON * exact).max(1e-12);
        let err = (r.cond2 / exact - 1.0).abs();
        eprintln!(
            "{:26} {:>26}  cond₂ {:.6e} err {err:.1e} (tol {tol:.1e})  bounds [{:.6e}, {:.6e}] \
             width {:.1e} proven {}  [{}]",
            case.case,
            r.route.name(),
            exact,
            r.cond2_lo,
            r.cond2_hi,
            r.relative_width(),
            r.bounds_proven,
            case.engine
        );
        if err > tol {
            failures.push(format!("{}: cond₂ error {err:e} > {tol:e}", case.case));
        }
        if !(r.cond2_lo <= exact * (1.0 + u) && exact * (1.0 - u) <= r.cond2_hi) {
            failures.push(format!(
                "{}: exact {exact:e} outside [{:e}, {:e}]",
                case.case, r.cond2_lo, r.cond2_hi
            ));
        }
        // The saddle points' brackets (σ_min's lower end by Temple's bound, second order, or
        // through the Schur complement onto B where the negative eigenvalues cluster): at the
        // contract's floor of 1e-12 (before them, 9.2e-7 on the beam, 1.1e-11 on the membrane,
        // 0.48 on the quad block and unproven on the tetrahedra).
        if case.saddle_dofs.is_some() && r.relative_width() > 1e-12 {
            failures.push(format!(
                "{}: saddle bracket width {:e} > 1e-12",
                case.case,
                r.relative_width()
            ));
        }
        // σ_max and σ_min themselves, each within the contract's share.
        check_extremes(
            &case.case,
            &r,
            &case.sigma_max,
            &case.sigma_min,
            tol,
            &mut failures,
        );
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
