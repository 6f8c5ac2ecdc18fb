//! The printed report of `solver_cost`: each family's finest level, rule by rule, and the
//! slopes against h.

use super::{slopes, Row};
use std::fmt::Write;

fn opt(v: Option<f64>, prec: usize) -> String {
    v.filter(|x| x.is_finite())
        .map_or("—".into(), |x| format!("{x:.prec$e}"))
}

fn count(v: Option<usize>, conv: Option<bool>) -> String {
    match (v, conv) {
        (Some(i), Some(false)) => format!("{i}*"),
        (Some(i), _) => i.to_string(),
        _ => "—".into(),
    }
}

/// The report (module doc). Iterations are counted to the fixed error of u; `*`: the run did
/// not reach it (iteration limit, or a breakdown of the preconditioned CG). The last columns show the residual-stopped
/// Jacobi run (‖r‖ ≤ τ‖b‖) and the error of u where it stopped.
pub fn text(all: &[Row]) -> String {
    let (map, rows): (Vec<Row>, Vec<Row>) = all.iter().cloned().partition(|r| r.in_eps_map());
    let rows = &rows[..];
    let mut t = String::new();
    let mut fams: Vec<&str> = Vec::new();
    for r in rows {
        if !fams.contains(&r.family.as_str()) {
            fams.push(&r.family);
        }
    }
    for fam in fams {
        let finest = rows
            .iter()
            .filter(|r| r.family == fam)
            .map(|r| r.level)
            .max()
            .unwrap_or(0);
        let first = rows.iter().find(|r| r.family == fam && r.level == finest);
        let (n, h, e) = first.map_or((0, f64::NAN, f64::NAN), |r| {
            (r.n_dofs, r.h, r.err_discretization)
        });
        let _ = writeln!(
            t,
            "\n{fam}, finest level ({n} DOFs, h = {h:.4}, discretization error {e:.2e})\n"
        );
        t.push_str("| rule | accuracy | knob (rel) | matched | cond₂ | cond₂ Jacobi | CG Jacobi | CG IC(0) / MINRES | CG AMG (scalar) | CG AMG (nodal) | IC(0) shift | digits lost (u) | err forces | direct (s) | CG IC(0) (s) | CG Jacobi to τ | err u at τ |\n");
        t.push_str(
            "|---|---|---:|:-:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
        );
        for r in rows.iter().filter(|r| r.family == fam && r.level == finest) {
            let krylov = match r.minres_iters_to_err {
                Some(_) => count(r.minres_iters_to_err, r.minres_iters_to_err_converged),
                None => count(r.pcg_iters_ic0_to_err, r.pcg_iters_ic0_to_err_converged),
            };
            let _ = writeln!(
                t,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.method,
                r.accuracy,
                opt(r.knob_rel, 2),
                if r.matched { "yes" } else { "no" },
                opt(r.cond2_system, 3),
                opt(r.cond2_jacobi, 3),
                count(
                    r.pcg_iters_jacobi_to_err,
                    r.pcg_iters_jacobi_to_err_converged
                ),
                krylov,
                count(
                    r.pcg_iters_amg_scalar_to_err,
                    r.pcg_iters_amg_scalar_to_err_converged
                ),
                count(
                    r.pcg_iters_amg_nodal_to_err,
                    r.pcg_iters_amg_nodal_to_err_converged
                ),
                r.ic0_shift.map_or("—".into(), |a| format!("{a:.3}")),
                r.digits_lost().map_or("—".into(), |d| format!("{d:.1}")),
                opt(r.forward_err_force, 1),
                opt(r.seconds_direct, 1),
                opt(r.seconds_pcg_ic0.or(r.seconds_minres), 1),
                count(r.pcg_iters_jacobi, r.pcg_converged_jacobi),
                opt(r.pcg_err_u_at_stop_jacobi, 1),
            );
        }
    }
    t.push_str("\nSlopes against h (cond₂ ∝ h^−p, iterations to the error target ∝ h^−q; least squares over the matched levels)\n\n");
    t.push_str("| family | rule | accuracy | levels | p cond₂ | p cond₂ Jacobi | q CG Jacobi | q CG IC(0) / MINRES |\n");
    t.push_str("|---|---|---|---:|---:|---:|---:|---:|\n");
    let f = |v: Option<f64>| v.map_or("—".into(), |x| format!("{x:.2}"));
    let slope_rows = slopes(rows);
    for s in slope_rows {
        let _ = writeln!(
            t,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            s.family,
            s.method,
            s.accuracy,
            s.levels_matched,
            f(s.p_cond2),
            f(s.p_cond2_jacobi),
            f(s.q_pcg_jacobi),
            f(s.q_pcg_ic0.or(s.q_minres)),
        );
    }
    t.push_str(&eps_map_text(&map));
    t
}

/// The ε map's table: per family, iterations to the error target (`*`: missed, at the
/// iteration limit or at a breakdown of the preconditioned CG), IC(0)'s shift and the digits of u a direct solve loses, against ε.
fn eps_map_text(map: &[Row]) -> String {
    let mut t = String::new();
    let mut fams: Vec<&str> = Vec::new();
    for r in map {
        if !fams.contains(&r.family.as_str()) {
            fams.push(&r.family);
        }
    }
    for fam in fams {
        let first = map.iter().find(|r| r.family == fam);
        let (level, n) = first.map_or((0, 0), |r| (r.level, r.n_dofs));
        let _ = writeln!(
            t,
            "\nε map, {fam} level {level} ({n} DOFs): constant at ε = ε/k_scale · k_scale; iterations to ‖u − u*‖∞ ≤ e‖u*‖∞\n"
        );
        t.push_str("| ε/k_scale | CG Jacobi | CG IC(0) | CG AMG (scalar) | CG AMG (nodal) | IC(0) shift | cond₂ Jacobi | digits lost (u) | max penetration | CG Jacobi to τ | err u at τ |\n");
        t.push_str("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for r in map.iter().filter(|r| r.family == fam) {
            let _ = writeln!(
                t,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                opt(r.knob_rel, 0),
                count(
                    r.pcg_iters_jacobi_to_err,
                    r.pcg_iters_jacobi_to_err_converged
                ),
                count(r.pcg_iters_ic0_to_err, r.pcg_iters_ic0_to_err_converged),
                count(
                    r.pcg_iters_amg_scalar_to_err,
                    r.pcg_iters_amg_scalar_to_err_converged
                ),
                count(
                    r.pcg_iters_amg_nodal_to_err,
                    r.pcg_iters_amg_nodal_to_err_converged
                ),
                r.ic0_shift.map_or("—".into(), |a| format!("{a:.3}")),
                opt(r.cond2_jacobi, 2),
                r.digits_lost().map_or("—".into(), |d| format!("{d:.1}")),
                opt(r.max_penetration, 1),
                count(r.pcg_iters_jacobi, r.pcg_converged_jacobi),
                opt(r.pcg_err_u_at_stop_jacobi, 1),
            );
        }
    }
    t
}
