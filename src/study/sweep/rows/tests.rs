//! The row format: the fast writer against the plain CSV writer, bit-exact read-back, the
//! tally of a file, and what a torn or short file is refused for.

use super::*;

/// The plain way: one `String` per cell, `{:e}` for floats, csv's `write_record`.
fn reference(rows: &[Row]) -> String {
    let fl = |x: Option<f64>| match x {
        Some(v) if v.is_finite() => format!("{v:e}"),
        Some(v) if v.is_nan() => String::new(),
        Some(v) if v > 0.0 => "inf".into(),
        Some(_) => "-inf".into(),
        None => String::new(),
    };
    let wh = |x: Option<usize>| x.map(|v| v.to_string()).unwrap_or_default();
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    for r in rows {
        w.write_record([
            r.scene.clone(),
            r.family.clone(),
            r.n.to_string(),
            r.m.to_string(),
            r.storage.clone(),
            r.nnz.to_string(),
            r.half_bandwidth.to_string(),
            r.method.clone(),
            fl(r.eps),
            fl(r.factor),
            fl(r.delta),
            fl(r.delta_rel),
            fl(r.eps_min),
            fl(r.eps_max),
            wh(r.active),
            fl(r.cond2_system),
            fl(r.cond2_k),
            fl(r.cond2_system_lo),
            fl(r.cond2_system_hi),
            fl(r.cond2_k_lo),
            fl(r.cond2_k_hi),
            fl(r.cond_tol),
            r.cond_route.clone().unwrap_or_default(),
            r.cond2_bounds_proven
                .map(|c| c.to_string())
                .unwrap_or_default(),
            r.cond2_within_contract
                .map(|c| c.to_string())
                .unwrap_or_default(),
            fl(r.log10_det_ratio),
            fl(r.max_penetration),
            fl(r.error_vs_exact),
            wh(r.linear_solves),
            wh(r.iterations),
            fl(r.kappa_initial),
            fl(r.kappa_final),
            wh(r.kappa_increases),
            r.converged.map(|c| c.to_string()).unwrap_or_default(),
            fl(r.seconds),
            fl(r.seconds_solve),
            fl(r.seconds_cond),
            fl(r.seconds_det),
            fl(r.cond_ratio_to_optimal),
            fl(r.cond2_jacobi),
            wh(r.pcg_iters_jacobi),
            wh(r.pcg_iters_ic0),
            r.pcg_converged.map(|c| c.to_string()).unwrap_or_default(),
            wh(r.minres_iters),
            wh(r.pcg_iters_jacobi_to_err),
            r.pcg_iters_jacobi_to_err_converged
                .map(|c| c.to_string())
                .unwrap_or_default(),
            wh(r.pcg_iters_ic0_to_err),
            r.pcg_iters_ic0_to_err_converged
                .map(|c| c.to_string())
                .unwrap_or_default(),
            wh(r.minres_iters_to_err),
            r.minres_iters_to_err_converged
                .map(|c| c.to_string())
                .unwrap_or_default(),
            wh(r.pcg_iters_amg_scalar_to_err),
            r.pcg_iters_amg_scalar_to_err_converged
                .map(|c| c.to_string())
                .unwrap_or_default(),
            wh(r.pcg_iters_amg_nodal_to_err),
            r.pcg_iters_amg_nodal_to_err_converged
                .map(|c| c.to_string())
                .unwrap_or_default(),
            fl(r.forward_err_u),
            fl(r.forward_err_force),
            fl(r.seconds_solver),
            r.warnings.clone(),
        ])
        .unwrap();
    }
    String::from_utf8(w.into_inner().unwrap()).unwrap()
}

/// Rows with every kind of cell: ±0, subnormals, extremes, ±inf, NaN, empty, and text
/// that needs quoting.
fn samples() -> Vec<Row> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(10);
    let special = [
        0.0,
        -0.0,
        5e-324,
        f64::MIN_POSITIVE,
        f64::MAX,
        -f64::MAX,
        1e16,
        1e-7,
        0.1,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    let texts = [
        "",
        "a,b",
        "say \"hi\"",
        "two\nlines",
        " lead",
        "ü; ok",
        "cr\r\nlf",
    ];
    (0..300)
        .map(|i| {
            let mut x = |k: usize| -> Option<f64> {
                match (i + k) % 5 {
                    0 => None,
                    1 => Some(special[(i * 7 + k) % special.len()]),
                    2 => Some(f64::from_bits(rng.random::<u64>())),
                    _ => Some(rng.random::<f64>() * 10f64.powi(rng.random_range(-30..30))),
                }
            };
            let w = |k: usize| (i % (k + 2) != 0).then_some(i * 31 + k);
            Row {
                scene: texts[i % texts.len()].into(),
                family: texts[(i + 1) % texts.len()].into(),
                n: i,
                m: usize::MAX - i,
                storage: "dense".into(),
                nnz: i * i,
                half_bandwidth: i % 7,
                method: texts[(i + 2) % texts.len()].into(),
                eps: x(0),
                factor: x(1),
                delta: x(2),
                delta_rel: x(3),
                eps_min: x(4),
                eps_max: x(5),
                active: w(0),
                cond2_system: x(6),
                cond2_k: x(7),
                cond2_system_lo: x(15),
                cond2_system_hi: x(16),
                cond2_k_lo: x(17),
                cond2_k_hi: x(18),
                cond_tol: x(19),
                cond_route: (i % 3 != 0).then(|| texts[(i + 3) % texts.len()].into()),
                cond2_bounds_proven: [Some(true), None, Some(false)][i % 3],
                cond2_within_contract: [Some(false), Some(true), None][i % 3],
                log10_det_ratio: x(8),
                max_penetration: x(9),
                error_vs_exact: x(10),
                linear_solves: w(1),
                iterations: w(2),
                kappa_initial: x(20),
                kappa_final: x(21),
                kappa_increases: w(3),
                converged: [None, Some(true), Some(false)][i % 3],
                seconds: x(11),
                seconds_solve: x(12),
                seconds_cond: x(13),
                seconds_det: x(14),
                cond_ratio_to_optimal: x(15),
                cond2_jacobi: x(16),
                pcg_iters_jacobi: w(4),
                pcg_iters_ic0: w(5),
                pcg_converged: [Some(true), Some(false), None][i % 3],
                minres_iters: w(6),
                pcg_iters_jacobi_to_err: w(7),
                pcg_iters_jacobi_to_err_converged: [None, Some(false), Some(true)][i % 3],
                pcg_iters_ic0_to_err: w(8),
                pcg_iters_ic0_to_err_converged: [Some(false), None, Some(true)][i % 3],
                minres_iters_to_err: w(9),
                minres_iters_to_err_converged: [Some(true), None, Some(false)][i % 3],
                pcg_iters_amg_scalar_to_err: w(10),
                pcg_iters_amg_scalar_to_err_converged: [None, Some(true), Some(false)][i % 3],
                pcg_iters_amg_nodal_to_err: w(11),
                pcg_iters_amg_nodal_to_err_converged: [Some(false), Some(true), None][i % 3],
                forward_err_u: x(17),
                forward_err_force: x(18),
                seconds_solver: x(19),
                warnings: texts[(i + 4) % texts.len()].into(),
            }
        })
        .collect()
}

#[test]
fn rows_format_as_the_plain_csv_writer_does() {
    let rows = samples();
    assert_eq!(format_rows(&rows), reference(&rows));
}

#[test]
fn formatted_rows_read_back_bit_for_bit() {
    let rows = samples();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rows.csv");
    std::fs::write(&path, header() + &format_rows(&rows)).unwrap();
    let (back, _) = read_rows(&path, false).unwrap();
    assert_eq!(back.len(), rows.len());
    // NaN is written as an empty cell and reads back as None; everything else is exact.
    let nan_to_none = |x: Option<f64>| x.filter(|v| !v.is_nan()).map(f64::to_bits);
    for (a, b) in rows.iter().zip(&back) {
        assert_eq!(nan_to_none(a.eps), b.eps.map(f64::to_bits));
        assert_eq!(
            nan_to_none(a.cond2_system),
            b.cond2_system.map(f64::to_bits)
        );
        assert_eq!(nan_to_none(a.seconds_det), b.seconds_det.map(f64::to_bits));
        assert_eq!(
            (a.m, &a.warnings, a.converged),
            (b.m, &b.warnings, b.converged)
        );
        assert_eq!(
            (a.cond2_bounds_proven, a.cond2_within_contract),
            (b.cond2_bounds_proven, b.cond2_within_contract)
        );
        assert_eq!(
            (
                a.pcg_iters_jacobi_to_err,
                a.pcg_iters_jacobi_to_err_converged,
                a.pcg_iters_ic0_to_err_converged,
                a.minres_iters_to_err,
                a.minres_iters_to_err_converged,
                a.pcg_iters_amg_scalar_to_err,
                a.pcg_iters_amg_scalar_to_err_converged,
                a.pcg_iters_amg_nodal_to_err,
                a.pcg_iters_amg_nodal_to_err_converged
            ),
            (
                b.pcg_iters_jacobi_to_err,
                b.pcg_iters_jacobi_to_err_converged,
                b.pcg_iters_ic0_to_err_converged,
                b.minres_iters_to_err,
                b.minres_iters_to_err_converged,
                b.pcg_iters_amg_scalar_to_err,
                b.pcg_iters_amg_scalar_to_err_converged,
                b.pcg_iters_amg_nodal_to_err,
                b.pcg_iters_amg_nodal_to_err_converged
            )
        );
    }
}

#[test]
fn counted_rows_are_the_rows_read() {
    let rows = samples();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rows.csv");
    let text = header() + &format_rows(&rows);
    std::fs::write(&path, &text).unwrap();
    let (read, _) = read_rows(&path, false).unwrap();
    assert_eq!(tally_rows(&path).unwrap().rows(), read.len());
    // What read_rows refuses, tally_rows refuses: a torn last line, a short record, a
    // foreign header.
    std::fs::write(&path, &text[..text.len() - 3]).unwrap();
    assert!(read_rows(&path, false).is_err() && tally_rows(&path).is_err());
    std::fs::write(&path, header() + "a,b,c\n").unwrap();
    assert!(read_rows(&path, false).is_err() && tally_rows(&path).is_err());
    std::fs::write(&path, "x,y\n").unwrap();
    assert!(tally_rows(&path).is_err());
}
