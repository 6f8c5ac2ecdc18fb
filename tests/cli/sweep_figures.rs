//! Tests for `penalty_lab::study::sweep::figures`: the quantile helper against hand-computed values,
//! and `render_all` on synthetic rows (file names, skipped figures, errors).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use penalty_lab::stats::{median, quantile};
use penalty_lab::study::sweep::figures::{build_figures, render_all, FIGURE_KINDS};
use penalty_lab::study::sweep::rows::Row;

/// A folder path for `render_all` to create, inside a fresh temporary folder (the guard).
fn out_dir(name: &str) -> (tempfile::TempDir, PathBuf) {
    let tmp = crate::common::tmp_dir(&format!("sweep-figures-{name}"));
    let dir = tmp.path().join("figures");
    (tmp, dir)
}

// ---------------------------------------------------------------------------------------------
// quantile
// ---------------------------------------------------------------------------------------------

#[test]
fn quantile_matches_hand_computed_values() {
    // Sorted: 1 2 3 4; h = q (n − 1) = 3q.
    let mut v = vec![3.0, 1.0, 4.0, 2.0];
    assert_eq!(quantile(&mut v, 0.5), 2.5); // h = 1.5: 2 + 0.5·1
    assert_eq!(v, vec![1.0, 2.0, 3.0, 4.0], "sorted in place");
    assert!((quantile(&mut v, 0.1) - 1.3).abs() < 1e-12); // h = 0.3
    assert!((quantile(&mut v, 0.9) - 3.7).abs() < 1e-12); // h = 2.7
    assert_eq!(quantile(&mut v, 0.0), 1.0);
    assert_eq!(quantile(&mut v, 1.0), 4.0);
    assert_eq!(quantile(&mut v, 1.0 / 3.0), 2.0); // h = 1 exactly
                                                  // The median is the q = ½ quantile: mean of the middle pair for an even count.
    assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), Some(2.5));
    assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
    assert_eq!(median(&[]), None);

    // Odd length: the median is the middle element.
    let mut v = vec![10.0, -5.0, 7.0, 0.0, 100.0];
    assert_eq!(quantile(&mut v, 0.5), 7.0);
    // h = 0.25·4 = 1: the second smallest.
    assert_eq!(quantile(&mut v, 0.25), 0.0);
    // h = 0.9·4 = 3.6: 10 + 0.6·(100 − 10) = 64.
    assert!((quantile(&mut v, 0.9) - 64.0).abs() < 1e-12);

    // Two values: h = q.
    let mut v = vec![20.0, 10.0];
    assert_eq!(quantile(&mut v, 0.25), 12.5);
    assert_eq!(quantile(&mut v, 0.5), 15.0);

    // One value, out-of-range q (clamped), empty input.
    let mut v = vec![5.0];
    assert_eq!(quantile(&mut v, 0.3), 5.0);
    let mut v = vec![1.0, 2.0, 3.0];
    assert_eq!(quantile(&mut v, -1.0), 1.0);
    assert_eq!(quantile(&mut v, 2.0), 3.0);
    assert!(quantile(&mut [], 0.5).is_nan());

    // Infinite values do not produce NaN when they coincide.
    let mut v = vec![1.0, f64::INFINITY, f64::INFINITY];
    assert_eq!(quantile(&mut v, 0.75), f64::INFINITY);
}

// ---------------------------------------------------------------------------------------------
// Synthetic rows
// ---------------------------------------------------------------------------------------------

/// A scene of the toy model: a contact stiffness `k` (≈ K[d,d]), a condensed stiffness
/// `k_s = k/3`, cond₂(K), the unconstrained gap scale `g0` = max_c |u0[d_c]| and m constraints.
#[derive(Clone, Copy)]
struct Toy {
    k: f64,
    cond_k: f64,
    g0: f64,
    m: usize,
}

impl Toy {
    fn ks(&self) -> f64 {
        self.k / 3.0
    }
    /// Penetration with a uniform penalty ε (1-DOF condensed spring).
    fn pen(&self, eps: f64) -> f64 {
        self.g0 * self.ks() / (self.ks() + eps)
    }
    /// cond₂ of K + D E Dᵀ: λ_max grows with the largest penalty.
    fn cond(&self, eps_max: f64) -> f64 {
        self.cond_k * (1.0 + eps_max / self.k)
    }
    fn det(&self, eps: f64) -> f64 {
        self.m as f64 * (1.0 + eps / self.ks()).log10()
    }
}

fn base(scene: &str, family: &str, method: &str, t: &Toy) -> Row {
    Row {
        scene: scene.into(),
        family: family.into(),
        n: 40,
        m: t.m,
        method: method.into(),
        cond2_k: Some(t.cond_k),
        ..Row::default()
    }
}

/// Rows of one scene: lagrange, constant over `eps_grid`, scaled, the three adaptive methods
/// over relative δ, augmented over tolerances. `cond`/`det`: whether those columns are filled.
fn scene_rows(scene: &str, family: &str, t: Toy, cond: bool, det: bool) -> Vec<Row> {
    let c = |x: f64| cond.then_some(x);
    let d = |x: f64| det.then_some(x);
    let mut rows = Vec::new();
    rows.push(Row {
        max_penetration: Some(0.0),
        error_vs_exact: Some(0.0),
        cond2_system: c(t.cond_k * 4.0),
        ..base(scene, family, "lagrange", &t)
    });
    for i in 0..=16 {
        let eps = 10f64.powf(i as f64 * 0.5);
        rows.push(Row {
            eps: Some(eps),
            eps_min: Some(eps),
            eps_max: Some(eps),
            max_penetration: Some(t.pen(eps)),
            cond2_system: c(t.cond(eps)),
            log10_det_ratio: d(t.det(eps)),
            ..base(scene, family, "constant", &t)
        });
    }
    for f in [1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3] {
        let eps = f * t.k;
        rows.push(Row {
            factor: Some(f),
            eps_min: Some(0.5 * eps),
            eps_max: Some(eps),
            max_penetration: Some(t.pen(0.8 * eps)),
            cond2_system: c(t.cond(eps)),
            log10_det_ratio: d(t.det(0.8 * eps)),
            ..base(scene, family, "scaled", &t)
        });
    }
    for rel in [1e-1, 1e-2, 1e-3] {
        let delta = rel * t.g0;
        // condensed: exactly δ.
        let e_c = t.ks() * (t.g0 / delta - 1.0);
        // paper (Eq. 28): over-stiffens by ~10×.
        let e_p = 10.0 * e_c;
        // spring: ignores coupling, somewhere in between.
        let e_s = 3.0 * e_c;
        for (method, e) in [("spring", e_s), ("paper", e_p), ("condensed", e_c)] {
            rows.push(Row {
                delta: Some(delta),
                delta_rel: Some(rel),
                eps_min: Some(0.3 * e),
                eps_max: Some(e),
                max_penetration: Some(t.pen(e)),
                cond2_system: c(t.cond(e)),
                log10_det_ratio: d(t.det(e)),
                ..base(scene, family, method, &t)
            });
        }
    }
    for rel in [1e-2, 1e-4, 1e-6] {
        // The sweep's choice: the geometric mean of the constrained diagonal of K.
        let eps = t.k;
        rows.push(Row {
            eps: Some(eps),
            delta: Some(rel * t.g0),
            delta_rel: Some(rel),
            eps_min: Some(eps),
            eps_max: Some(eps),
            max_penetration: Some(0.5 * rel * t.g0),
            cond2_system: c(t.cond(eps)),
            log10_det_ratio: d(t.det(eps)),
            iterations: Some(3 + (-rel.log10()) as usize),
            ..base(scene, family, "augmented", &t)
        });
    }
    rows
}

/// `scenes` scenes per family with spread stiffness, conditioning and displacement scales.
fn synthetic(families: &[&str], scenes: usize, cond: bool, det: bool) -> Vec<Row> {
    let mut rows = Vec::new();
    for (fi, fam) in families.iter().enumerate() {
        for s in 0..scenes {
            // Deterministic spread without an RNG.
            let a = ((s * 7 + fi * 3) % 11) as f64 / 10.0;
            let b = ((s * 5 + fi) % 7) as f64 / 6.0;
            let t = Toy {
                k: 10f64.powf(1.5 + 1.0 * a + fi as f64),
                cond_k: 10f64.powf(2.0 + 2.0 * b + 1.5 * fi as f64),
                g0: 10f64.powf(-1.0 - 0.5 * b),
                m: 3 + s % 4,
            };
            rows.extend(scene_rows(&format!("{fam}-{s}"), fam, t, cond, det));
        }
    }
    rows
}

fn names(paths: &[PathBuf]) -> BTreeSet<String> {
    paths
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect()
}

fn expected(kinds: &[&str], families: &[&str]) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for f in families {
        for k in kinds {
            for ext in ["png", "svg"] {
                out.insert(format!("{k}_{f}.{ext}"));
            }
        }
    }
    out
}

fn assert_written(dir: &Path, paths: &[PathBuf]) {
    for p in paths {
        assert_eq!(
            p.parent().unwrap(),
            dir,
            "{} outside {}",
            p.display(),
            dir.display()
        );
        let len = std::fs::metadata(p).unwrap().len();
        assert!(len > 1000, "{} is only {len} bytes", p.display());
    }
    let on_disk: BTreeSet<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(on_disk, names(paths), "files on disk = files returned");
}

// ---------------------------------------------------------------------------------------------
// render_all
// ---------------------------------------------------------------------------------------------

#[test]
fn writes_every_figure_for_every_family() {
    let rows = synthetic(&["beam", "spectrum"], 2, true, true);
    let (_tmp, dir) = out_dir("all");
    let paths = render_all(&rows, &dir).unwrap();
    assert_eq!(
        names(&paths),
        expected(&FIGURE_KINDS, &["beam", "spectrum"])
    );
    assert_written(&dir, &paths);
}

#[test]
fn missing_cond_skips_cond_figures() {
    // cond2_system empty in every row (and cond2_K too): cond_vs_eps and pareto are skipped.
    let mut rows = synthetic(&["beam", "spectrum"], 2, false, true);
    for r in &mut rows {
        r.cond2_k = None;
    }
    let (_tmp, dir) = out_dir("nocond");
    let paths = render_all(&rows, &dir).unwrap();
    assert_eq!(
        names(&paths),
        expected(
            &["penetration_vs_eps", "log_det_ratio_vs_eps"],
            &["beam", "spectrum"]
        )
    );
    assert_written(&dir, &paths);

    // Penetration only (the cheapest sweep).
    let rows = synthetic(&["membrane"], 2, false, false);
    let (_tmp2, dir2) = out_dir("penonly");
    let paths = render_all(&rows, &dir2).unwrap();
    assert_eq!(
        names(&paths),
        expected(&["penetration_vs_eps"], &["membrane"])
    );
}

#[test]
fn partial_columns_and_odd_families() {
    // Only lagrange and condensed for a file scene with an awkward family name; one
    // condensed row has no metrics at all (a failed solve).
    let t = Toy {
        k: 100.0,
        cond_k: 1e3,
        g0: 0.1,
        m: 3,
    };
    let mut rows: Vec<Row> = scene_rows("paper-beam.json", "file/x y", t, true, true)
        .into_iter()
        .filter(|r| r.method == "lagrange" || r.method == "condensed")
        .collect();
    let last = rows.last_mut().unwrap();
    last.cond2_system = None;
    last.max_penetration = None;
    last.log10_det_ratio = None;
    last.eps_max = None;
    last.warnings = "singular matrix".into();
    let (_tmp, dir) = out_dir("odd");
    let paths = render_all(&rows, &dir).unwrap();
    assert_eq!(names(&paths), expected(&FIGURE_KINDS, &["file_x_y"]));
}

#[test]
fn nothing_to_draw_is_not_an_error_but_no_rows_is() {
    let rows: Vec<Row> = synthetic(&["beam"], 2, false, false)
        .into_iter()
        .map(|r| Row {
            max_penetration: None,
            ..r
        })
        .collect();
    let (_tmp, dir) = out_dir("nothing");
    assert!(render_all(&rows, &dir).unwrap().is_empty());

    let err = render_all(&[], &dir).unwrap_err();
    assert!(
        matches!(err, penalty_lab::Error::NoneGiven { .. }) && err.to_string().contains("rows"),
        "{err}"
    );
}

#[test]
fn medians_bands_and_legends() {
    let rows = synthetic(&["beam"], 3, true, true);
    let figs = build_figures(&rows);
    let stems: Vec<&str> = figs.iter().map(|(s, _)| s.as_str()).collect();
    assert_eq!(
        stems,
        [
            "cond_vs_eps_beam",
            "penetration_vs_eps_beam",
            "pareto_beam",
            "log_det_ratio_vs_eps_beam"
        ]
    );
    let (_, pen) = &figs[1];
    assert!(
        pen.title.contains("beam") && pen.title.contains("3 scenes"),
        "{}",
        pen.title
    );

    // constant median at ε = 1 (grid point 0) is the median of the three scenes' values.
    // Penetration is relative to each scene's displacement scale g0 = delta / delta_rel.
    assert_eq!(pen.y_label, "max penetration / max_c |u0[d_c]|");
    let g0 = |scene: &str| {
        let r = rows
            .iter()
            .find(|r| r.scene == scene && r.delta_rel.is_some())
            .unwrap();
        r.delta.unwrap() / r.delta_rel.unwrap()
    };
    let mut at1: Vec<f64> = rows
        .iter()
        .filter(|r| r.method == "constant" && r.eps == Some(1.0))
        .map(|r| r.max_penetration.unwrap() / g0(&r.scene))
        .collect();
    at1.sort_by(f64::total_cmp);
    let med = pen
        .series
        .iter()
        .find(|s| s.label.starts_with("constant ε: median"))
        .unwrap();
    assert_eq!(med.x[0], 1.0);
    assert_eq!(med.y[0], at1[1]);
    let band = &pen.bands[0];
    assert!(band.label.contains("10–90 %"), "{}", band.label);
    assert!((band.lo[0] - (at1[0] + 0.2 * (at1[1] - at1[0]))).abs() < 1e-12 * at1[2]);
    assert!((band.hi[0] - (at1[1] + 0.8 * (at1[2] - at1[1]))).abs() < 1e-12 * at1[2]);

    // One series per adaptive method, δ listed with the relative unit.
    let cond = &figs[0].1;
    let condensed = cond
        .series
        .iter()
        .find(|s| s.label.starts_with("condensed"))
        .unwrap();
    assert_eq!(
        condensed.label,
        "condensed (exact δ) at δ = 1e-1, 1e-2, 1e-3·|u0| (left to right)"
    );
    assert_eq!(condensed.x.len(), 3);
    assert!(cond.hlines.iter().any(|(_, l)| l.starts_with("cond₂(K)")));

    // Pareto: lagrange as a labelled horizontal line, every penalty method as a series.
    let pareto = &figs[2].1;
    assert!(pareto
        .hlines
        .iter()
        .any(|(_, l)| l.starts_with("lagrange (exact, saddle point")));
    for m in [
        "constant",
        "scaled",
        "spring",
        "paper",
        "condensed",
        "augmented",
    ] {
        assert!(
            pareto.series.iter().any(|s| s.label.starts_with(m)),
            "no {m} series in the pareto figure"
        );
    }
}

#[test]
fn absolute_delta_keeps_absolute_penetration() {
    // Without relative δ the scenes' displacement scales are unknown: absolute penetration,
    // δ listed without the |u0| unit.
    let rows: Vec<Row> = synthetic(&["spectrum"], 2, true, true)
        .into_iter()
        .map(|r| Row {
            delta_rel: None,
            ..r
        })
        .collect();
    let figs = build_figures(&rows);
    let (stem, pen) = &figs[1];
    assert_eq!(stem, "penetration_vs_eps_spectrum");
    assert_eq!(pen.y_label, "max penetration (units of u)");
    let condensed = pen
        .series
        .iter()
        .find(|s| s.label.starts_with("condensed"))
        .unwrap();
    assert!(!condensed.label.contains("|u0|"), "{}", condensed.label);
    // The constant median is that of the raw values (two scenes: their mean).
    let at1: Vec<f64> = rows
        .iter()
        .filter(|r| r.method == "constant" && r.eps == Some(1.0))
        .map(|r| r.max_penetration.unwrap())
        .collect();
    let med = &pen.series[0];
    assert!((med.y[0] - 0.5 * (at1[0] + at1[1])).abs() <= 1e-12 * at1[0].max(at1[1]));
}

#[test]
fn unpenalised_adaptive_method_is_named_not_dropped() {
    // spring solved every δ but penalised nothing (eps_min/eps_max empty): it has no place on
    // the ε axis, so it appears as a legend-only entry saying so.
    let rows: Vec<Row> = synthetic(&["membrane"], 2, true, true)
        .into_iter()
        .map(|r| {
            if r.method == "spring" {
                Row {
                    eps_min: None,
                    eps_max: None,
                    ..r
                }
            } else {
                r
            }
        })
        .collect();
    let figs = build_figures(&rows);
    let cond = &figs[0].1;
    let spring = cond
        .series
        .iter()
        .find(|s| s.label.starts_with("spring"))
        .unwrap();
    assert!(spring.x.is_empty(), "{:?}", spring.x);
    assert!(spring.label.contains("not drawn"), "{}", spring.label);
    let (_tmp, dir) = out_dir("unpenalised");
    let paths = render_all(&rows, &dir).unwrap();
    assert_eq!(names(&paths), expected(&FIGURE_KINDS, &["membrane"]));
}

/// Renders a realistic synthetic sweep (3 families × 8 scenes) for visual inspection into
/// `$CARGO_TARGET_TMPDIR/sweep_figures_preview`.
#[test]
fn preview_realistic_sweep() {
    let rows = synthetic(&["beam", "membrane", "spectrum"], 8, true, true);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sweep_figures_preview");
    let _ = std::fs::remove_dir_all(&dir);
    let paths = render_all(&rows, &dir).unwrap();
    assert_eq!(paths.len(), 3 * FIGURE_KINDS.len() * 2);
}
