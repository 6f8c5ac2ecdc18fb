//! The contact benchmarks against their analytic solutions (Hertz, Johnson 1985 §4.2, §5.8;
//! the uniform pressure of the flat punch) on the default meshes: the benchmark's numbers,
//! computed by the library's study.

use penalty_lab::progress::Progress;
use penalty_lab::strategy::registry;
use penalty_lab::study::checkpoint::Checkpoints;
use penalty_lab::study::contact_bench::{self, analytic::Case, BenchConfig, BenchRun};

fn config() -> BenchConfig {
    BenchConfig {
        methods: registry::lookup_all(&["lagrange", "condensed"]).unwrap(),
        deltas_rel: vec![1e-3, 1e-5],
        ..BenchConfig::default()
    }
}

fn suite() -> BenchRun {
    contact_bench::run(&config(), &Progress::quiet(), None).unwrap()
}

#[test]
fn hertz_and_flat_punch_match_the_analytic_solutions() {
    let run = suite();
    let rows = run.rows;
    assert!(
        rows.iter().all(|r| r.error.is_empty()),
        "every solve succeeds"
    );
    let finest = rows.iter().map(|r| r.h).fold(f64::INFINITY, f64::min);
    for case in ["hertz-plane", "hertz-axi"] {
        // Finest default mesh: p0 within 3 %, a within 5 % (Lagrange and condensed, δ ≤ 1e-3·a).
        for r in rows.iter().filter(|r| r.case == case && r.h == finest) {
            let (p0, a) = (r.p0_num / r.p0_exact - 1.0, r.a_num / r.a_exact - 1.0);
            assert!(
                p0.abs() <= 0.03,
                "{case} {} {:?}: p0 off by {p0:.4}",
                r.method,
                r.knob_rel
            );
            assert!(
                a.abs() <= 0.05,
                "{case} {} {:?}: a off by {a:.4}",
                r.method,
                r.knob_rel
            );
            // Force control: every rule carries the load (these two: to `FORCE_TOL`).
            assert!(r.force_mismatch.abs() <= penalty_lab::strategy::force_control::FORCE_TOL);
        }
        // condensed under force control is Lagrange shifted by δ: the same pressures to the
        // rounding of the solves (cond₂(K) ≈ 1e7 here).
        for r in rows
            .iter()
            .filter(|r| r.case == case && r.method == "condensed")
        {
            assert!(
                r.err_penalty <= 1e-9,
                "{case} h = {}: {}",
                r.h,
                r.err_penalty
            );
        }
    }
    // The discretization error falls at least like h^0.8 over the three meshes.
    for (case, rate) in contact_bench::convergence_rates(&rows) {
        let rate = rate.expect("three meshes");
        assert!(rate >= 0.8, "{case}: rate {rate}");
    }
    // Flat punch: Lagrange and condensed give a uniform pressure to 1e-8, equal to p̄.
    for r in rows.iter().filter(|r| r.case == "flat-punch") {
        assert!(
            r.p_spread <= 1e-8,
            "{} {:?}: spread {}",
            r.method,
            r.knob_rel,
            r.p_spread
        );
        assert!(
            r.p_err_rel <= 1e-8,
            "{} {:?}: error {}",
            r.method,
            r.knob_rel,
            r.p_err_rel
        );
    }
}

/// The conditioning floor of each mesh (`optimal::cond2_lower_bound` from the certified
/// routes) bounds every penalized system's cond₂ from below, and on the coarsest flat-punch mesh
/// (60 DOFs) it is λ_max(K)/λ_min(K_FF) as nalgebra's dense eigensolver gives it (error
/// ≲ n·ε_mach·cond₂(K_FF) relative).
#[test]
fn every_penalized_system_is_above_its_floor() {
    let run = contact_bench::run(
        &BenchConfig {
            cases: vec![Case::FlatPunch, Case::HertzPlane],
            meshes: vec![0.2],
            ..config()
        },
        &Progress::quiet(),
        None,
    )
    .unwrap();
    assert_eq!(run.floors.len(), 2);
    for r in run.rows.iter().filter(|r| r.method != "lagrange") {
        let floor = run
            .floors
            .iter()
            .find(|f| f.case == r.case && f.h == r.h)
            .expect("a floor per mesh")
            .cond2_floor;
        let c = r.cond2_system.expect("cond₂");
        // cond₂ is reported to cond_tol.
        assert!(
            floor <= c * (1.0 + r.cond_tol),
            "{} {:?}: {c:e} < {floor:e}",
            r.case,
            r.knob_rel
        );
    }
    let cfg = config();
    let grid = cfg.grid(Case::FlatPunch, 0.2).unwrap();
    let scene = cfg.scene(Case::FlatPunch, &grid, 0.0).unwrap();
    let p = &scene.problem;
    let k = p.k.to_nalgebra();
    let n = p.n();
    let free: Vec<usize> = (0..n)
        .filter(|i| !p.constraints.iter().any(|c| c.single_dof().unwrap() == *i))
        .collect();
    let kff = nalgebra::DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let lmax = k.symmetric_eigenvalues().max();
    let ev = kff.symmetric_eigenvalues();
    let lmin = ev.min();
    let dense = lmax / lmin;
    let floor = run
        .floors
        .iter()
        .find(|f| f.case == "flat-punch")
        .unwrap()
        .cond2_floor;
    let tol = 16.0 * free.len() as f64 * f64::EPSILON * ev.max() / lmin;
    assert!(
        (floor / dense - 1.0).abs() <= tol,
        "floor {floor:e}, dense {dense:e} (tol {tol:e})"
    );
}

/// A run writes one checkpoint per mesh; a resumed run reads back those of the same build and
/// config (a row edited in the file comes back edited) and solves again where the config
/// differs or `resume` is off (the edit is gone).
#[test]
fn resumed_runs_reuse_matching_checkpoints_only() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = BenchConfig {
        cases: vec![Case::FlatPunch],
        meshes: vec![0.2],
        ..config()
    };
    let fresh = Checkpoints::new(dir.path(), "meshes", &cfg, false).unwrap();
    let first = contact_bench::run(&cfg, &Progress::quiet(), Some(&fresh)).unwrap();
    let file = fresh.dir.join("flat-punch-h0.2.json");
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(
        json["value"]["rows"].as_array().unwrap().len(),
        first.rows.len()
    );
    json["value"]["rows"][0]["seconds"] = serde_json::json!(-1.0);
    std::fs::write(&file, json.to_string()).unwrap();
    let marked = |run: &BenchRun| run.rows[0].seconds == -1.0;

    let resume = Checkpoints::new(dir.path(), "meshes", &cfg, true).unwrap();
    let resumed = contact_bench::run(&cfg, &Progress::quiet(), Some(&resume)).unwrap();
    assert!(marked(&resumed), "the checkpoint is reused");
    for (a, b) in first.rows.iter().zip(&resumed.rows).skip(1) {
        assert_eq!(a.cond2_system, b.cond2_system, "rows read back exactly");
        let same = |x: f64, y: f64| x == y || (x.is_nan() && y.is_nan());
        assert!(same(a.p_err_rel, b.p_err_rel) && same(a.err_penalty, b.err_penalty));
    }
    assert_eq!(first.floors, resumed.floors);

    let other = BenchConfig {
        cond_tol: 1e-5,
        ..cfg.clone()
    };
    let other_resume = Checkpoints::new(dir.path(), "meshes", &other, true).unwrap();
    let resolved = contact_bench::run(&other, &Progress::quiet(), Some(&other_resume)).unwrap();
    assert!(!marked(&resolved), "another config solves again");
    json["value"]["rows"][0]["seconds"] = serde_json::json!(-1.0);
    std::fs::write(&file, json.to_string()).unwrap();
    let again = contact_bench::run(&cfg, &Progress::quiet(), Some(&fresh)).unwrap();
    assert!(!marked(&again), "without resume every mesh is solved");
    Checkpoints::remove_in(dir.path(), "meshes").unwrap();
    assert!(!resume.dir.exists());
}

/// Force control takes `optimal` to its own tolerance (`optimal::LOAD_TOL`): on the 60-DOF
/// flat-punch mesh at δ = 1e-2·a the optimal force jumps with the lift, so the 1e-10 of exact rules
/// is out of reach there (with it, the bracket collapses at the jump with a mismatch of
/// 2.5e-10; the a9af79d rows, before Newton stages, failed after 40 solves); at 1e-6 every δ
/// carries the load within a few solves, and the mismatch is reported.
#[test]
fn force_control_takes_optimal_to_its_own_tolerance() {
    use penalty_lab::strategy::{force_control, optimal, Method};
    let run = contact_bench::run(
        &BenchConfig {
            cases: vec![Case::FlatPunch],
            meshes: vec![0.2],
            methods: registry::lookup_all(&["optimal"]).unwrap(),
            deltas_rel: vec![1e-2, 1e-3],
            ..BenchConfig::default()
        },
        &Progress::quiet(),
        None,
    )
    .unwrap();
    assert_eq!(run.rows.len(), 2);
    let tol = Method::optimal(1e-3).strategy().force_tol;
    assert_eq!(tol, optimal::LOAD_TOL);
    assert!(tol > force_control::FORCE_TOL);
    for r in &run.rows {
        assert!(r.error.is_empty(), "{:?}: {}", r.knob_rel, r.error);
        assert!(
            r.force_mismatch.abs() <= tol,
            "{:?}: {}",
            r.knob_rel,
            r.force_mismatch
        );
        assert!(
            r.force_solves <= 10,
            "{:?}: {} solves",
            r.knob_rel,
            r.force_solves
        );
    }
}

/// The leaderboard discriminates: every winner's penalty error is within a
/// tenth of the discretization error; where a rule's admissibility flips between two decade
/// values, two more values between them were solved (three per decade at the threshold), so
/// the winner's softer neighbour is at most a third of a decade away; each winner's
/// resolution is the cond₂ step to that neighbour, and a rule within it of the mesh's
/// cheapest is a tie, never a loss.
#[test]
fn the_leaderboard_has_a_margin_a_refined_threshold_and_ties() {
    let cfg = BenchConfig {
        cases: vec![Case::HertzPlane],
        meshes: vec![0.2],
        methods: registry::lookup_all(&["lagrange", "constant", "condensed"]).unwrap(),
        ..BenchConfig::default()
    };
    let run = contact_bench::run(&cfg, &Progress::quiet(), None).unwrap();
    let leaders = contact_bench::leaderboard(&run.rows);
    let constant = leaders.iter().find(|l| l.rule == "constant").unwrap();
    let k = constant.knob_rel.expect("constant has an admissible ε");
    assert!(constant.err_penalty.unwrap() <= contact_bench::MARGIN * constant.err_discretization);
    // The softer neighbour tried is within a third of a decade (refined), and failed.
    let softer: Vec<_> = run
        .rows
        .iter()
        .filter(|r| r.method == "constant" && r.knob_rel.is_some_and(|v| v < k))
        .collect();
    let nearest = softer
        .iter()
        .max_by(|a, b| a.knob_rel.unwrap().total_cmp(&b.knob_rel.unwrap()))
        .unwrap();
    assert!(k / nearest.knob_rel.unwrap() <= 10f64.powf(1.0 / 3.0) * (1.0 + 1e-12));
    assert!(!contact_bench::admissible(nearest));
    let res = constant.resolution.expect("a softer knob exists");
    let want = (constant.cond2_system.unwrap() / nearest.cond2_system.unwrap() - 1.0).abs();
    assert_eq!(res, want);
    // Ties: the cheapest rule ties itself; a tie is within the larger resolution.
    let best = leaders
        .iter()
        .filter_map(|l| l.cond2_system.map(|c| (c, l)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap();
    assert!(best.1.tied_best);
    for l in leaders.iter().filter(|l| l.tied_best) {
        let r = l
            .resolution
            .unwrap_or(0.0)
            .max(best.1.resolution.unwrap_or(0.0));
        assert!(l.cond2_system.unwrap() / best.0 - 1.0 <= r, "{}", l.rule);
    }
}

/// `constant`'s ε is per unit contact length/area: node c gets ε·ω_c. On the
/// flat punch any ε then gives the exact uniform pressure (a uniform penetration is a rigid
/// shift) — a nodal ε equal on every node, as before, loaded the half-weight edge node like
/// the others and spread the pressure; on Hertz the axis node, whose tributary area is the
/// smallest, no longer spikes above Lagrange's peak (it was 1.47 p0 in plane strain and 1.9 p0
/// axisymmetric), and the penalty error at one ε barely moves with h.
#[test]
fn constant_penalty_is_per_unit_contact_area() {
    let cfg = BenchConfig {
        cases: vec![Case::FlatPunch, Case::HertzPlane, Case::HertzAxi],
        meshes: vec![0.2, 0.1],
        methods: registry::lookup_all(&["lagrange", "constant"]).unwrap(),
        eps_rel: vec![1.0, 10.0, 1e3],
        ..BenchConfig::default()
    };
    let rows = contact_bench::run(&cfg, &Progress::quiet(), None)
        .unwrap()
        .rows;
    let constant = |case: &str| -> Vec<&contact_bench::BenchRow> {
        rows.iter()
            .filter(|r| r.case == case && r.method == "constant" && r.knob == "eps")
            .collect()
    };
    for r in constant("flat-punch") {
        let tol = r.n_dofs as f64 * f64::EPSILON;
        assert!(
            r.p_spread <= tol,
            "ε/(E*/a) = {:?}: spread {:e}",
            r.knob_rel,
            r.p_spread
        );
        assert!(
            r.err_penalty <= tol,
            "{:?}: {:e}",
            r.knob_rel,
            r.err_penalty
        );
    }
    for case in ["hertz-plane", "hertz-axi"] {
        for r in constant(case) {
            let lag = rows
                .iter()
                .find(|l| l.case == case && l.method == "lagrange" && l.h == r.h)
                .unwrap();
            assert!(
                r.p0_num <= lag.p0_num * (1.0 + 1e-3),
                "{case} h = {} ε/(E*/a) = {:?}: axis pressure {} above Lagrange's {}",
                r.h,
                r.knob_rel,
                r.p0_num,
                lag.p0_num
            );
        }
        // One ε, two meshes: the penalty error moves by less than a third.
        for rel in [1.0, 10.0, 1e3] {
            let e: Vec<f64> = constant(case)
                .into_iter()
                .filter(|r| r.knob_rel == Some(rel))
                .map(|r| r.err_penalty)
                .collect();
            assert_eq!(e.len(), 2);
            assert!(
                (e[0] / e[1] - 1.0).abs() <= 1.0 / 3.0,
                "{case} ε/(E*/a) = {rel}: penalty errors {e:?}"
            );
        }
    }
}

/// The domain study: Lagrange on blocks of 16a … 1024a at the same contact
/// mesh. The distance from the reference block falls with the block size (∝ L⁻² in plane
/// strain, ∝ L⁻³ axisymmetric: at least 8× per 4× size), so the reference's own residue is
/// below the next block's; the rows' `err_discretization` is the reference block's error and
/// their `err_domain` the benchmark block's distance, and the benchmark block's total error
/// (Lagrange's `p_err_rel`) lies within `err_domain` of the discretization error (triangle
/// inequality of the norm). Without the block's bias the plane-strain error converges at the
/// rate the √(a − x) edge allows for Q4, 1 (the referee's large-block fit: 1.00).
#[test]
fn domain_error_is_measured_and_removed_from_the_discretization_error() {
    use contact_bench::domain::DOMAIN_SIZES;
    let cfg = BenchConfig {
        cases: vec![Case::HertzPlane, Case::HertzAxi],
        meshes: vec![0.2, 0.1],
        methods: registry::lookup_all(&["lagrange"]).unwrap(),
        ..BenchConfig::default()
    };
    let run = contact_bench::run(&cfg, &Progress::quiet(), None).unwrap();
    assert_eq!(run.domain.len(), 2 * 2 * DOMAIN_SIZES.len());
    for r in &run.rows {
        let d: Vec<_> = run
            .domain
            .iter()
            .filter(|d| d.case == r.case && d.h == r.h)
            .collect();
        let reference = d.last().unwrap();
        assert_eq!(reference.err_domain, 0.0);
        assert_eq!(
            r.err_discretization, reference.err_total,
            "{} h = {}",
            r.case, r.h
        );
        let own = d
            .iter()
            .find(|d| d.block_over_a == cfg.block_over_a)
            .unwrap();
        assert_eq!(r.err_domain, own.err_domain);
        for w in d[..d.len() - 1].windows(2) {
            assert!(
                w[1].err_domain * 8.0 <= w[0].err_domain,
                "{} h = {}: {} → {}",
                r.case,
                r.h,
                w[0].err_domain,
                w[1].err_domain
            );
        }
        let gap = (r.p_err_rel - r.err_discretization).abs();
        assert!(
            gap <= r.err_domain * (1.0 + 1e-6),
            "{} h = {}: |{} − {}| > {}",
            r.case,
            r.h,
            r.p_err_rel,
            r.err_discretization,
            r.err_domain
        );
    }
    let plane = contact_bench::convergence_rates(&run.rows)
        .into_iter()
        .find(|(c, _)| c == "hertz-plane")
        .and_then(|(_, r)| r)
        .unwrap();
    assert!((plane - 1.0).abs() <= 0.05, "plane-strain rate {plane}");
}

/// The inclined-plane cases (rows with two terms): Lagrange and `condensed` carry the load with
/// the flat punch's uniform pressure (spread ≤ 1e-8 over the loaded nodes), `condensed` within
/// δ; the rows say `theta` and `discretization`, and the floor over all E (written for a
/// Boolean D) is NaN, not an error.
#[test]
fn inclined_cases_give_the_uniform_pressure_with_two_term_rows() {
    let cfg = BenchConfig {
        cases: vec![Case::Inclined15, Case::Inclined30, Case::Inclined45],
        meshes: vec![0.2, 0.1],
        methods: registry::lookup_all(&["lagrange", "condensed"]).unwrap(),
        deltas_rel: vec![1e-2, 1e-4],
        ..config()
    };
    let run = contact_bench::run(&cfg, &Progress::quiet(), None).unwrap();
    assert_eq!(run.rows.len(), 3 * 2 * 3);
    for r in &run.rows {
        let what = format!("{} {} {:?} h = {}", r.case, r.method, r.knob_rel, r.h);
        assert!(r.error.is_empty(), "{what}: {}", r.error);
        assert_eq!(r.discretization, "nodal");
        assert_eq!(r.theta, Case::from_name(&r.case).unwrap().theta_deg());
        assert!(r.theta > 0.0);
        assert!(r.p_spread <= 1e-8, "{what}: spread {}", r.p_spread);
        assert!(
            r.force_mismatch <= 1e-8,
            "{what}: load {}",
            r.force_mismatch
        );
        if let Some(rel) = r.knob_rel {
            let delta = rel * r.lift;
            assert!(r.max_penetration <= delta, "{what}: {}", r.max_penetration);
        }
    }
    // The floor over all penalties (K on the null space of the two-term rows' Dᵀ) lies below
    // every penalized system's cond₂ on its mesh.
    for f in &run.floors {
        assert!(f.cond2_floor.is_finite() && f.cond2_floor >= 1.0, "{f:?}");
        let mesh_rows: Vec<_> = run
            .rows
            .iter()
            .filter(|r| {
                r.case == f.case && (r.h - f.h).abs() <= 1e-12 * f.h && r.method == "condensed"
            })
            .collect();
        assert_eq!(mesh_rows.len(), 2, "{f:?}");
        for r in mesh_rows {
            let cond = r.cond2_system.unwrap();
            assert!(
                f.cond2_floor <= cond,
                "{f:?} above {} cond₂ {cond:e}",
                r.method
            );
        }
    }
}

/// The two-body patch test in the benchmark: mortar's Lagrange and `condensed` rows carry the
/// load with the uniform pressure (spread ≤ 1e-8), one-pass node-to-segment's Lagrange is off by
/// percents (reported as its discretization error), and the rows say the discretization, the
/// mesh ratio and the upper block's material.
#[test]
fn two_body_patch_cases_report_mortar_exact_and_nts_off() {
    let cfg = BenchConfig {
        cases: vec![Case::PatchMortar, Case::PatchNts1],
        meshes: vec![0.2, 0.1],
        methods: registry::lookup_all(&["lagrange", "condensed"]).unwrap(),
        deltas_rel: vec![1e-2, 1e-4],
        ..config()
    };
    let run = contact_bench::run(&cfg, &Progress::quiet(), None).unwrap();
    assert_eq!(run.rows.len(), 2 * 2 * 3);
    for r in &run.rows {
        let what = format!("{} {} {:?} h = {}", r.case, r.method, r.knob_rel, r.h);
        assert!(r.error.is_empty(), "{what}: {}", r.error);
        let ratio = r.mesh_ratio.unwrap();
        assert!(
            ratio > 1.0 && ratio.fract() != 0.0,
            "{what}: non-matching, {ratio}"
        );
        assert_eq!(r.young2, Some(cfg.young / 3.0));
        if r.case == "patch-two-body-mortar" {
            assert_eq!(r.discretization, "mortar");
            assert!(r.p_spread <= 1e-8, "{what}: spread {}", r.p_spread);
            assert!(r.err_discretization <= 1e-8, "{what}");
        } else {
            assert_eq!(r.discretization, "nts-1");
            assert!(
                r.err_discretization > 1e-3,
                "{what}: {}",
                r.err_discretization
            );
        }
        if let Some(rel) = r.knob_rel {
            assert!(r.max_penetration <= rel * r.lift, "{what}");
        }
    }
}

/// `--mesh-ratio` (ratios such as 2:3, 3:5, 4:7): at h = a/10 (10 lower elements
/// across) the upper block gets 15, 17 and 18 elements; mortar's Lagrange and `condensed`
/// keep the uniform pressure to 1e-8 at each, one-pass node-to-segment is off by more than
/// 1e-3, and the rows record the ratio they ran.
#[test]
fn two_body_patch_holds_at_every_mesh_ratio() {
    for ((up, low), upper) in [((3, 2), 15.0), ((5, 3), 17.0), ((7, 4), 18.0)] {
        let cfg = BenchConfig {
            cases: vec![Case::PatchMortar, Case::PatchNts1],
            meshes: vec![0.1],
            methods: registry::lookup_all(&["lagrange", "condensed"]).unwrap(),
            deltas_rel: vec![1e-3],
            mesh_ratio: (up, low),
            ..config()
        };
        let run = contact_bench::run(&cfg, &Progress::quiet(), None).unwrap();
        assert_eq!(run.rows.len(), 2 * 2);
        for r in &run.rows {
            let what = format!("{up}:{low} {} {} {:?}", r.case, r.method, r.knob_rel);
            assert!(r.error.is_empty(), "{what}: {}", r.error);
            assert_eq!(r.mesh_ratio, Some(upper / 10.0), "{what}");
            if r.case == "patch-two-body-mortar" {
                assert!(r.p_spread <= 1e-8, "{what}: spread {}", r.p_spread);
            } else {
                assert!(
                    r.err_discretization > 1e-3,
                    "{what}: {}",
                    r.err_discretization
                );
            }
        }
    }
    let bad = BenchConfig {
        mesh_ratio: (0, 4),
        ..config()
    };
    assert!(bad
        .validate()
        .unwrap_err()
        .to_string()
        .contains("--mesh-ratio"));
}

/// `hertz-two-body` in the benchmark (coarsest default mesh, h = a/5): Lagrange and
/// `condensed` meet Hertz with the pair's E* within the acceptance bar (p0 3 %, a 5 %; the
/// finest mesh is checked in `two_body::elastic_cylinder_on_elastic_block_meets_hertz`), the
/// rows say mortar, the mesh ratio, the cylinder's material and radius, and `condensed` keeps
/// every gap row within δ.
#[test]
fn hertz_two_body_case_meets_hertz_and_records_the_second_body() {
    let cfg = BenchConfig {
        cases: vec![Case::HertzTwoBody],
        meshes: vec![0.2],
        methods: registry::lookup_all(&["lagrange", "condensed"]).unwrap(),
        deltas_rel: vec![1e-3],
        ..config()
    };
    let run = contact_bench::run(&cfg, &Progress::quiet(), None).unwrap();
    assert_eq!(run.rows.len(), 2);
    for r in &run.rows {
        let what = format!("{} {:?}", r.method, r.knob_rel);
        assert!(r.error.is_empty(), "{what}: {}", r.error);
        assert_eq!(r.discretization, "mortar");
        assert_eq!(r.mesh_ratio, Some(7.0 / 4.0));
        assert_eq!(r.young2, Some(cfg.young / 3.0));
        assert_eq!(r.poisson2, Some(0.33));
        assert_eq!(r.radius2, Some(cfg.radius));
        assert!((r.p0_num / r.p0_exact - 1.0).abs() <= 0.03, "{what}: p0");
        assert!((r.a_num / r.a_exact - 1.0).abs() <= 0.05, "{what}: a");
        if let Some(rel) = r.knob_rel {
            assert!(r.max_penetration <= rel * cfg.a_target, "{what}");
        }
    }
}

/// `hertz-normals`: the rigid cylinder with every row along its nodal normal (two terms off
/// the axis, unit rows). On the coarsest default mesh Lagrange and `condensed` meet Hertz as
/// the vertical rows do (p0 within 3 %, a within 5 %), and the two row forms differ by less
/// than the mesh's discretization error (the normals turn by at most x/R = 0.16 rad inside
/// the contact zone of 1.5a).
#[test]
fn hertz_with_nodal_normals_meets_hertz() {
    let cfg = BenchConfig {
        cases: vec![Case::HertzNormals, Case::HertzPlane],
        meshes: vec![0.2],
        methods: registry::lookup_all(&["lagrange", "condensed"]).unwrap(),
        deltas_rel: vec![1e-3],
        ..config()
    };
    let setup = cfg.setup();
    let grid = cfg.grid(Case::HertzNormals, 0.2).unwrap();
    let scene = setup.scene(Case::HertzNormals, &grid, 0.05).unwrap();
    let mut coupled = 0;
    for c in &scene.problem.constraints {
        let n2: f64 = c.terms.iter().map(|t| t.1 * t.1).sum();
        assert!((n2 - 1.0).abs() <= 4.0 * f64::EPSILON, "{:?}", c.terms);
        coupled += usize::from(c.terms.len() == 2);
    }
    assert_eq!(
        coupled,
        scene.problem.m() - 1,
        "all rows but the axis node's couple"
    );
    let run = contact_bench::run(&cfg, &Progress::quiet(), None).unwrap();
    let lag = |case: &str| {
        run.rows
            .iter()
            .find(|r| r.case == case && r.method == "lagrange")
            .unwrap()
    };
    for r in run.rows.iter().filter(|r| r.case == "hertz-normals") {
        let what = format!("{} {:?}", r.method, r.knob_rel);
        assert!(r.error.is_empty(), "{what}: {}", r.error);
        assert!((r.p0_num / r.p0_exact - 1.0).abs() <= 0.03, "{what}: p0");
        assert!((r.a_num / r.a_exact - 1.0).abs() <= 0.05, "{what}: a");
    }
    let (n, v) = (lag("hertz-normals"), lag("hertz-plane"));
    assert!(
        (n.p0_num / v.p0_num - 1.0).abs() <= v.err_discretization,
        "{} vs {}",
        n.p0_num,
        v.p0_num
    );
}
