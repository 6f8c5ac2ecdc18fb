//! The printed report of `penalty_scaling`: each discretization's finest level, rule by rule,
//! and the slopes against h.

use super::{slopes, Row};
use std::fmt::Write;

fn opt(v: Option<f64>, prec: usize) -> String {
    v.filter(|x| x.is_finite())
        .map_or("—".into(), |x| format!("{x:.prec$e}"))
}

fn count(v: Option<usize>) -> String {
    v.map_or("—".into(), |i| i.to_string())
}

/// The report (module doc).
pub fn text(rows: &[Row]) -> String {
    let mut t = String::new();
    let mut discs: Vec<&str> = Vec::new();
    for r in rows {
        if !discs.contains(&r.discretization.as_str()) {
            discs.push(&r.discretization);
        }
    }
    for disc in discs {
        let of = |r: &&Row| r.discretization == disc;
        let finest = rows.iter().filter(of).map(|r| r.level).max().unwrap_or(0);
        let first = rows.iter().filter(of).find(|r| r.level == finest);
        let (n, m, h) = first.map_or((0, 0, f64::NAN), |r| (r.n_dofs, r.n_rows, r.h));
        let _ = writeln!(
            t,
            "\n{disc}, finest level ({n} DOFs, {m} rows, h = {h:.4})\n"
        );
        t.push_str("| rule | knob | err u | err penalty | err pressure | max penetration | cond₂ | cond₂ Jacobi | CG Jacobi | CG IC(0) / MINRES | note |\n");
        t.push_str("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
        for r in rows.iter().filter(of).filter(|r| r.level == finest) {
            let _ = writeln!(
                t,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.label(),
                opt(r.knob_value, 2),
                opt(r.err_u, 2),
                opt(r.err_penalty, 2),
                opt(r.err_pressure, 2),
                opt(r.max_penetration, 2),
                opt(r.cond2_system, 3),
                opt(r.cond2_jacobi, 3),
                count(r.pcg_iters_jacobi_to_err),
                count(r.pcg_iters_ic0_to_err.or(r.minres_iters_to_err)),
                r.note.chars().take(80).collect::<String>(),
            );
        }
    }
    t.push_str("\nSlopes against h (cond₂ ∝ h^−p, error ∝ h^s; least squares over the levels)\n\n");
    t.push_str(
        "| discretization | rule | levels | p cond₂ | p cond₂ Jacobi | s err u | s err penalty |\n",
    );
    t.push_str("|---|---|---:|---:|---:|---:|---:|\n");
    let f = |v: Option<f64>| v.map_or("—".into(), |x| format!("{x:.2}"));
    for s in slopes(rows) {
        let label = Row {
            method: s.method.clone(),
            schedule: s.schedule.clone(),
            eps_rel: s.eps_rel,
            ..Row::default()
        }
        .label();
        let _ = writeln!(
            t,
            "| {} | {} | {} | {} | {} | {} | {} |",
            s.discretization,
            label,
            s.levels,
            f(s.p_cond2),
            f(s.p_cond2_jacobi),
            f(s.s_err_u),
            f(s.s_err_penalty),
        );
    }
    t
}
