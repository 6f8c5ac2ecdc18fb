//! Long studies keep each finished unit of work (`study::checkpoint`): `solver_cost` per mesh
//! level, `friction_bench` per Cattaneo–Mindlin (mesh, μ). A run with `--resume` reads back
//! the checkpoints of the same build and configuration (an edit planted in one comes back) and
//! otherwise gives the uninterrupted run's rows; without `--resume` everything is solved again.

use penalty_lab::progress::Progress;
use penalty_lab::strategy::registry;
use penalty_lab::study::checkpoint::Checkpoints;
use penalty_lab::study::{friction_bench, solver_cost};
use std::path::Path;

/// Plants `value` at the JSON pointer `at` of the checkpoint `file`.
fn plant(file: &Path, at: &str, value: serde_json::Value) {
    let mut c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    *c.pointer_mut(at).expect("the planted field exists") = value;
    std::fs::write(file, c.to_string()).unwrap();
}

#[test]
fn solver_cost_resumes_from_its_level_checkpoints() {
    let cfg = solver_cost::SolverCostConfig {
        families: vec![solver_cost::Family::Beam],
        levels: 2,
        methods: registry::lookup_all(&["constant"]).unwrap(),
        ..Default::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let quiet = Progress::quiet();
    let fresh = Checkpoints::new(dir.path(), solver_cost::CHECKPOINTS, &cfg, false).unwrap();
    let first = solver_cost::run(&cfg, &quiet, Some(&fresh)).unwrap();
    let level1 = fresh.dir.join("beam-level1.json");
    assert!(fresh.dir.join("beam-level0.json").exists() && level1.exists());
    plant(&level1, "/value/rows/0/seconds_search", (-1.0).into());

    let resume = Checkpoints::new(dir.path(), solver_cost::CHECKPOINTS, &cfg, true).unwrap();
    let resumed = solver_cost::run(&cfg, &quiet, Some(&resume)).unwrap();
    assert_eq!(first.len(), resumed.len());
    let planted: Vec<_> = resumed
        .iter()
        .filter(|r| r.seconds_search == -1.0)
        .collect();
    assert_eq!(planted.len(), 1, "the level's checkpoint is read back");
    assert_eq!(planted[0].level, 1);
    let json = |r: &solver_cost::Row| {
        let mut v = serde_json::to_value(r).unwrap();
        for k in ["seconds_search", "seconds_metrics"] {
            v[k] = serde_json::Value::Null;
        }
        v
    };
    for (a, b) in first.iter().zip(&resumed) {
        assert_eq!(json(a), json(b), "rows read back exactly, timings aside");
    }
    let again = solver_cost::run(&cfg, &quiet, Some(&fresh)).unwrap();
    assert!(
        again.iter().all(|r| r.seconds_search >= 0.0),
        "without --resume every level is solved"
    );
    Checkpoints::remove_in(dir.path(), solver_cost::CHECKPOINTS).unwrap();
    assert!(!fresh.dir.exists());
}

#[test]
fn friction_bench_resumes_from_its_cattaneo_mindlin_checkpoints() {
    let cfg = friction_bench::BenchConfig {
        cases: vec![friction_bench::cattaneo::CASE.into()],
        mu: vec![0.2],
        cm_levels: vec![0.125],
        q_over_mup: vec![0.5],
        cm_eps_t: vec![],
        cm_delta_t: vec![1e-3],
        ..Default::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let quiet = Progress::quiet();
    let case = friction_bench::cattaneo::CASE;
    let fresh = Checkpoints::new(dir.path(), case, &cfg, false).unwrap();
    let first = friction_bench::run(&cfg, &quiet, Some(&fresh)).unwrap();
    assert!(first.len() >= 2);
    let file = fresh.dir.join(format!("{case}-h0.125-mu0.2.json"));
    plant(&file, "/value/0/warnings", "planted".into());
    let resume = Checkpoints::new(dir.path(), case, &cfg, true).unwrap();
    let resumed = friction_bench::run(&cfg, &quiet, Some(&resume)).unwrap();
    assert_eq!(
        resumed[0].warnings, "planted",
        "the checkpoint is read back"
    );
    assert_eq!(first.len(), resumed.len());
    let other = friction_bench::BenchConfig {
        q_over_mup: vec![0.25],
        ..cfg.clone()
    };
    let other = Checkpoints::new(dir.path(), case, &other, true).unwrap();
    assert_eq!(
        other
            .read::<Vec<friction_bench::FrictionRow>>(&format!("{case}-h0.125-mu0.2"))
            .unwrap()
            .map(|r| r.len()),
        None,
        "another configuration's checkpoint is not read"
    );
}
