//! The `paper_beam` experiment end to end: JSON comparison, figures, `--render-only`.
//! The disagreeing entries must be exactly the paper's two misprints (Eq. 33 entry 7 and
//! Eq. 37 entry 3, see tests/paper_beam.rs for their derivation).

use std::process::Command;

#[test]
fn paper_beam_marks_exactly_the_misprints_and_writes_figures() {
    let out = std::env::temp_dir().join(format!("pl-paper-beam-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_paper_beam"))
        .args(["--json", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = v["paper_comparison"].as_array().unwrap();
    assert!(rows.len() >= 25, "{} rows", rows.len());
    let disagree: Vec<&str> = rows
        .iter()
        .filter(|r| r["agree"] == serde_json::json!(false))
        .map(|r| r["id"].as_str().unwrap())
        .collect();
    assert_eq!(disagree.len(), 2, "{disagree:?}");
    assert!(disagree.iter().any(|id| id.contains("33")), "{disagree:?}");
    assert!(disagree.iter().any(|id| id.contains("37")), "{disagree:?}");
    let figs = [
        "fig3_deflection_free",
        "fig4_deflection_contact",
        "cond_vs_eps",
    ];
    for f in figs {
        for ext in ["png", "svg"] {
            let p = out.join(format!("{f}.{ext}"));
            assert!(
                std::fs::metadata(&p).map(|m| m.len() > 0).unwrap_or(false),
                "{p:?}"
            );
        }
    }
    // Re-render from the saved data only.
    for f in figs {
        std::fs::remove_file(out.join(format!("{f}.png"))).unwrap();
    }
    let o = Command::new(env!("CARGO_BIN_EXE_paper_beam"))
        .args(["--render-only", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in figs {
        assert!(out.join(format!("{f}.png")).exists());
    }
}
