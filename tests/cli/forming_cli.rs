//! CLI contract of `deep_drawing` and `stretch_test`: JSON shape, `--out` files, bad input →
//! exit status 2 with one line on stderr.

use crate::common;
use std::process::Command;

/// Runs `bin`; without `--out` in `args`, into a fresh temporary folder (the binaries write
/// into `--out`, whose default is under `results/`).
fn run(bin: &str, args: &[&str]) -> std::process::Output {
    let tmp = tempfile::tempdir().expect("temp dir");
    let mut cmd = Command::new(bin);
    cmd.args(args);
    if !args.contains(&"--out") && !args.contains(&"--help") {
        cmd.arg("--out").arg(tmp.path());
    }
    cmd.output().expect("binary runs")
}

const DD: &str = env!("CARGO_BIN_EXE_deep_drawing");
const TE: &str = env!("CARGO_BIN_EXE_stretch_test");
/// `stretch_test` under its former name, as older commands run it.
const TE_ALIAS: &str = env!("CARGO_BIN_EXE_test_example");

#[test]
fn bad_input_exits_with_status_2_and_one_line() {
    let tmp = common::tmp_dir("forming-bad");
    // A config file in the temp folder; its path.
    let file = |name: &str, text: &str| {
        let path = tmp.path().join(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_string()
    };
    let bad_toml = file("bad.toml", "penalty = 1e7\n[forming]\nelemnts = 3\n");
    // A value of the wrong type: the message names its line (the typed conversion has none).
    let typed = file(
        "typed.toml",
        "penalty = 1e7\n\n[forming]\nelements = 3\nsteps = \"ten\"\n",
    );
    let top = file(
        "top.toml",
        "delta = 1e-5\npenalty = true\n[forming]\nsteps = 4\n",
    );
    // A key's name inside a multi-line string is not its line; a header may carry a comment.
    let mls = file(
        "mls.toml",
        "[forming] # the run\nname = \"\"\"\nsteps = 4\n\"\"\"\nelements = 3\nsteps = \"ten\"\n",
    );
    // Values that parse but fail validation: their key and line (a nested table's too), or
    // the flag that set them.
    let invalid = file(
        "invalid.toml",
        "penalty = 1e7\n[forming]\n# a comment\nsteps = 0\n",
    );
    let nested = file(
        "nested.toml",
        "[forming]\nsteps = 4\n[forming.punch]\nradius = -2.0\n",
    );
    let cases: Vec<(&str, Vec<&str>, &str)> = vec![
        (
            DD,
            vec!["--config", &invalid],
            "invalid.toml: line 4: `steps`",
        ),
        (
            DD,
            vec!["--config", &nested],
            "nested.toml: line 4: `radius`",
        ),
        (
            DD,
            vec!["--config", &invalid, "--steps", "0"],
            "--steps: steps",
        ),
        (DD, vec!["--elements", "1"], "elements"),
        (DD, vec!["--delta", "-1"], "δ"),
        (DD, vec!["--penalty", "0"], "penalty"),
        (DD, vec!["--travel", "nan"], "travel"),
        (DD, vec!["--friction", "-0.1"], "friction"),
        (DD, vec!["--config", "/nonexistent/x.toml"], "nonexistent"),
        (DD, vec!["--config", &bad_toml], "elemnts"),
        (DD, vec!["--config", &bad_toml], "line 3"),
        (DD, vec!["--config", &typed], "line 5"),
        (DD, vec!["--config", &top], "line 2"),
        (DD, vec!["--config", &mls], "line 6"),
        (TE, vec!["--steps", "0"], "steps"),
    ];
    for (bin, args, needle) in cases {
        let o = run(bin, &args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: '{err}' lacks '{needle}'");
    }
}

#[test]
fn json_shapes_and_out_files() {
    let tmp = common::tmp_dir("forming-out");
    let dir = tmp.path().join("out");
    let small = [
        "--steps",
        "12",
        "--elements",
        "20",
        "--travel",
        "0.12",
        "--json",
    ];
    let mut args = small.to_vec();
    let out = dir.to_str().unwrap();
    args.extend(["--out", out]);
    let o = run(DD, &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["runs"]["classical"]["eps"], 1e7);
    assert_eq!(v["runs"]["adaptive"]["delta"], 1e-5);
    for run in ["classical", "adaptive"] {
        let steps = v["runs"][run]["steps"].as_array().unwrap();
        assert_eq!(steps.len(), 12);
        for key in [
            "step",
            "punch_travel",
            "punch_force",
            "cond2",
            "log10_det",
            "max_penetration",
            "volume",
            "iterations",
            "contact_nodes",
        ] {
            assert!(steps[0].get(key).is_some(), "{run} step lacks {key}");
        }
    }
    common::assert_files(
        &dir,
        &[
            "deep_drawing.json",
            "steps_classical.csv",
            "steps_adaptive.csv",
            "fig7_condition_per_step.png",
            "fig7_condition_per_step.svg",
            "punch_force_vs_travel.png",
            "thickness_strain.png",
            "deformed_profiles.svg",
        ],
    );
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("deep_drawing.json")).unwrap())
            .unwrap();
    assert_ne!(saved["provenance"]["git_commit"], serde_json::Value::Null);
    assert_eq!(saved["config"]["elements"], 20);

    // --render-only redraws the figures from the saved JSON alone and prints the same runs.
    let stdout = common::assert_render_only(
        DD,
        &dir,
        "fig7_condition_per_step.png",
        "deep_drawing.json",
        &["--json"],
    );
    let again: serde_json::Value = serde_json::from_slice(&stdout).unwrap();
    assert_eq!(again["runs"], v["runs"]);

    let o = run(TE, &small);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let last = |r: &str| v["runs"][r]["steps"].as_array().unwrap().last().unwrap()["cond2"].clone();
    assert_eq!(v["cond2_classical"], last("classical"));
    assert_eq!(v["cond2_adaptive"], last("adaptive"));
    assert!(v["cond2_classical"].as_f64().unwrap() > 0.0);
    assert_eq!(v["cond2_classical_matched"], last("classical-matched"));
    // Two δ-rules against two classical runs, in each of the five metrics.
    let comparisons = v["comparisons"].as_array().unwrap();
    assert_eq!(comparisons.len(), 4 * 5);
    for metric in [
        "cond2",
        "cond2_jacobi",
        "pcg_iters_jacobi_to_err",
        "pcg_iters_ic0_to_err",
        "forward_err_u",
    ] {
        assert_eq!(
            comparisons.iter().filter(|c| c["metric"] == metric).count(),
            4,
            "{metric}"
        );
    }
    // Every step carries the solver-cost metrics of its last system.
    for (name, run) in v["runs"].as_object().unwrap() {
        for s in run["steps"].as_array().unwrap() {
            assert!(s["cond2_jacobi"].as_f64().unwrap() >= 1.0, "{name}: {s}");
            assert!(s["pcg_iters_ic0"].as_u64().is_some(), "{name}: {s}");
            assert!(s["pcg_iters_ic0_to_err"].as_u64().is_some(), "{name}: {s}");
            let fe = s["forward_err_u"].as_f64().unwrap();
            let bound = 1e3 * f64::EPSILON * s["cond2"].as_f64().unwrap();
            assert!(
                fe <= bound,
                "{name}: forward error {fe:e} above 1e3·ε·cond₂ = {bound:e}"
            );
        }
    }
}

/// Both experiments carry `classical-matched`: a constant ε whose largest penetration over
/// the run, recomputed here from the steps, lies in [δ/2, δ] — the classical penalty at the
/// δ-rules' accuracy — and the δ-rules are compared with it step by step.
#[test]
fn classical_matched_penetrates_between_half_delta_and_delta() {
    for bin in [DD, TE, TE_ALIAS] {
        let o = run(bin, &["--json"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let m = &v["runs"]["classical-matched"];
        let delta = v["runs"]["adaptive"]["delta"].as_f64().unwrap();
        let eps = m["eps"].as_f64().unwrap();
        assert!(eps > 0.0 && eps < 1e7, "{bin}: ε = {eps}");
        let largest = m["steps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["max_penetration"].as_f64().unwrap())
            .fold(0.0, f64::max);
        assert!(
            (0.5 * delta..=delta).contains(&largest),
            "{bin}: largest penetration {largest} outside [δ/2, δ], δ = {delta}"
        );
        assert_eq!(m["largest_penetration"].as_f64().unwrap(), largest);
        assert_eq!(m["valid"], true, "{bin}: {:?}", m["invalid_reasons"]);
        // The search's cost is recorded: at least the returned run's own factorizations.
        let own: u64 = m["steps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["factorizations"].as_u64().unwrap())
            .sum();
        let search = &m["search"];
        let runs = search["runs"].as_u64().unwrap();
        assert!((1..=12).contains(&runs), "{bin}: {search}");
        assert!(
            search["factorizations"].as_u64().unwrap() >= own,
            "{bin}: {search}"
        );
        assert!(v["runs"]["classical"]["search"].is_null());
    }
}

#[test]
fn runs_outside_the_model_exit_3_with_one_line_and_allow_invalid_keeps_them_marked() {
    // --travel 100 pushes the punch 100 in through a 2.2 in blank.
    for bin in [DD, TE] {
        let o = run(bin, &["--travel", "100", "--json"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(3), "{bin}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{bin}: {err}");
        assert!(err.contains("outside the model"), "{bin}: {err}");
        assert!(o.stdout.is_empty(), "{bin}: printed a result");
        let o = run(bin, &["--travel", "100", "--json", "--allow-invalid"]);
        assert_eq!(o.status.code(), Some(0), "{bin}");
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["valid"], false, "{bin}");
        let reasons = v["invalid_reasons"].as_array().unwrap();
        assert!(
            reasons
                .iter()
                .any(|r| r.as_str().unwrap().contains("longer than")),
            "{bin}: {reasons:?}"
        );
    }
    let o = run(DD, &["--help"]);
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(help.contains("3 the run left") && help.contains("--allow-invalid"));
}

#[test]
fn the_default_run_is_valid_and_a_small_blank_is_drawn_off_the_holder() {
    let o = run(DD, &["--json"]);
    assert_eq!(o.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["valid"], true, "{:?}", v["invalid_reasons"]);
    // A 1.4 in blank on a die whose flat starts at 1.313 in: the rim is drawn off the flat
    // (under the holder) around 0.6 in of travel.
    let tmp = common::tmp_dir("forming-flange");
    let toml = tmp.path().join("small_blank.toml");
    std::fs::write(&toml, "[forming]\nblank_radius = 1.4\n").unwrap();
    let toml = toml.to_str().unwrap();
    let o = run(DD, &["--config", toml, "--json"]);
    assert_eq!(o.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&o.stderr).contains("drawn off the holder"));
    let o = run(DD, &["--config", toml, "--json", "--allow-invalid"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["valid"], false);
    assert_eq!(v["runs"]["adaptive"]["valid"], false);
}
