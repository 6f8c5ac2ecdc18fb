//! The AMG evaluation: kryst's preconditioners under kryst's CG on the systems that
//! `membrane_systems.py` and `elasticity_systems.py` write to data/ (the PyAMG side of the
//! comparison is in those scripts). Every configuration is timed as `KspContext::setup`
//! (preconditioner setup) and `KspContext::solve` (CG from x0 = 0).
//!
//! Stopping rule: kryst's CG with `ksp_cg_norm = unprecond`, rtol 1e-8, atol 0, i.e.
//! ||r_k||_2 <= 1e-8 ||r_0||_2 = 1e-8 ||b||_2 on CG's recursively updated residual. That is
//! PyAMG's criterion (`criteria='rr'`). kryst's own default for CG is the preconditioned norm
//! sqrt(r^T M r) relative to sqrt(b^T M b); its iteration count is printed too ("prec-norm").
//! The true relative residual ||b - A x||_2 / ||b||_2 is recomputed after every solve.
//!
//! Configurations:
//!   jacobi      PcType::Jacobi.
//!   amg-default PcType::Amg with no options (HMIS-based coarsening with MIS-2 on the first
//!               level, extended classical interpolation, symmetric Gauss-Seidel 1/1, CG
//!               coarse solve): the first round's configuration.
//!   sa          AMGBuilder: interpolation_type(Multipass), which in kryst 4.3.0 is the path
//!               that smooths the tentative aggregation prolongator with one damped-Jacobi
//!               step (omega = 2/3) = smoothed aggregation; agg_num_levels(0) (plain MIS-1
//!               aggregation on every level, no aggressive first level); DirectDense coarse
//!               solve; everything else default (SGS 1/1, strength 0.25, coarse size 9).
//!               Scalar: near-null space = constant vector.
//!   sa-nodal    elasticity only: `sa` plus nodal(true, 2) (nodal strength and aggregation,
//!               block 2) with kryst's default nodal near-null space (the two translations).
//!   sa-nodal-rbm  elasticity only: `sa-nodal` plus near_nullspace([t_x, t_y, rotation])
//!               read from data/elastic{n}_B.mtx (the three rigid-body modes).
//!   sa-mis2, sa-nodal-rbm-mis2  the same with agg_num_levels(25): MIS-2 aggregation on
//!               every level (closer to PyAMG's standard aggregation).
//! `run_kryst.sh` runs each (system, configuration) pair as `amg_eval SYSTEM CONFIG` in its own
//! process under a time and memory limit; `AMG_EVAL_DIAG=SYSTEM` prints one SA hierarchy.
//! The AMGBuilder configurations are handed to KspContext with `set_pc_box_for_tests`, the
//! only public way kryst 4.3.0 has to install a preconditioner object built by hand.
use kryst::context::ksp_context::{KspContext, SolverType};
use kryst::context::pc_context::PcType;
use kryst::matrix::backend::DefaultDenseMat;
use kryst::matrix::csr::CsrMatrix;
use kryst::matrix::op::{GenericCsrOp, LinOp};
use kryst::matrix::spmv::plan::SpmvTuning;
use kryst::preconditioner::amg::{AMGBuilder, CoarseSolve, InterpType, RelaxPhase};
use kryst::preconditioner::Preconditioner;
use kryst::KspOptions;
use std::io::Write;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;
use std::time::Instant;

fn mm_body(path: &str) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .filter(|l| !l.starts_with('%') && !l.trim().is_empty())
        .map(|l| l.to_string())
        .collect()
}

fn read_coo(path: &str) -> (usize, Vec<(usize, usize, f64)>) {
    let lines = mm_body(path);
    let head: Vec<usize> = lines[0]
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    let t = lines[1..]
        .iter()
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (
                f[0].parse::<usize>().unwrap() - 1,
                f[1].parse::<usize>().unwrap() - 1,
                f[2].parse::<f64>().unwrap(),
            )
        })
        .collect();
    (head[0], t)
}

/// A dense Matrix Market array (column-major) as its columns.
fn read_dense(path: &str) -> Vec<Vec<f64>> {
    let lines = mm_body(path);
    let head: Vec<usize> = lines[0]
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    let (m, k) = (head[0], head[1]);
    let v: Vec<f64> = lines[1..]
        .iter()
        .map(|l| l.trim().parse().unwrap())
        .collect();
    assert_eq!(v.len(), m * k, "{path}");
    (0..k).map(|j| v[j * m..(j + 1) * m].to_vec()).collect()
}

fn to_op(n: usize, mut t: Vec<(usize, usize, f64)>) -> Arc<dyn LinOp<S = f64>> {
    t.sort_by(|a, b| (a.0, a.1).cmp(&(b.0, b.1)));
    let mut rp = vec![0usize; n + 1];
    for &(i, _, _) in &t {
        rp[i + 1] += 1;
    }
    for i in 0..n {
        rp[i + 1] += rp[i];
    }
    let ci: Vec<usize> = t.iter().map(|e| e.1).collect();
    let v: Vec<f64> = t.iter().map(|e| e.2).collect();
    let csr = Arc::new(CsrMatrix::<f64>::new(n, n, rp, ci, v));
    Arc::new(GenericCsrOp::new(csr, &SpmvTuning::default()))
}

#[derive(Clone)]
enum Pc {
    Jacobi,
    AmgDefault,
    Sa {
        nodal: bool,
        nns: Option<Vec<Vec<f64>>>,
        agg_levels: usize,
    },
}

fn sa_builder(nodal: bool, nns: &Option<Vec<Vec<f64>>>, agg_levels: usize) -> AMGBuilder {
    let mut b = AMGBuilder::new()
        .interpolation_type(InterpType::Multipass)
        .agg_num_levels(agg_levels)
        .coarse_solve(CoarseSolve::DirectDense)
        .num_grid_sweeps(RelaxPhase::Coarsest, 0);
    // Diagnostic knob only (not set by run_kryst.sh): kryst's strength threshold, default 0.25.
    if let Ok(v) = std::env::var("AMG_EVAL_THETA") {
        b = b.strong_threshold(v.parse().unwrap());
    }
    if nodal {
        b = b.nodal(true, 2);
    }
    if let Some(basis) = nns {
        b = b.near_nullspace(basis.clone());
    }
    b
}

fn build_sa(
    nodal: bool,
    nns: &Option<Vec<Vec<f64>>>,
    agg_levels: usize,
) -> Box<dyn Preconditioner> {
    Box::new(
        sa_builder(nodal, nns, agg_levels)
            .build(&DefaultDenseMat::<f64>::zeros(0, 0))
            .unwrap(),
    )
}

/// `AMG_EVAL_DIAG=membrane63 cargo run --release`: set up `sa` (or `sa-nodal-rbm` for an
/// elastic system) once with kryst's statistics on and print the hierarchy and setup timings.
fn diagnose(name: &str) {
    let (n, t) = read_coo(&format!("data/{name}_A.mtx"));
    let a = to_op(n, t);
    let (nodal, nns) = if name.starts_with("elastic") {
        (true, Some(read_dense(&format!("data/{}_B.mtx", name))))
    } else {
        (false, None)
    };
    let agg = std::env::var("AMG_EVAL_AGG_LEVELS").map_or(0, |v| v.parse().unwrap());
    let mut amg = sa_builder(nodal, &nns, agg)
        .logging_level(1)
        .build(&DefaultDenseMat::<f64>::zeros(0, 0))
        .unwrap();
    let t0 = Instant::now();
    amg.setup(&*a).unwrap();
    println!("{name}: setup {:.3} s", t0.elapsed().as_secs_f64());
    if let Some(s) = amg.stats() {
        println!(
            "levels {} grid cx {:.2} op cx {:.2}",
            s.num_levels, s.grid_complexity, s.operator_complexity
        );
        for l in &s.levels {
            println!(
                "  level {} n {} nnz {} coarse {:?}",
                l.level, l.n, l.nnz_a, l.coarse_solver
            );
        }
        for (i, l) in s.setup.per_level.iter().enumerate() {
            println!("  timing {i}: {l:?}");
        }
        println!("  total {:?}", s.setup.total_setup);
    }
}

struct Outcome {
    iters: usize,
    reason: String,
    setup_s: f64,
    solve_s: f64,
    relres: f64,
}

fn run(a: &Arc<dyn LinOp<S = f64>>, b: &[f64], pc: &Pc, norm: &str) -> Result<Outcome, String> {
    let n = b.len();
    let mut ksp = KspContext::new();
    let opts = KspOptions {
        cg_norm: Some(norm.to_string()),
        ..Default::default()
    };
    ksp.set_from_options(&opts).map_err(|e| format!("{e}"))?;
    ksp.set_type(SolverType::Cg).map_err(|e| format!("{e}"))?;
    match pc {
        Pc::Jacobi => {
            ksp.set_pc_type(PcType::Jacobi, None)
                .map_err(|e| format!("{e}"))?;
        }
        Pc::AmgDefault => {
            ksp.set_pc_type(PcType::Amg, None)
                .map_err(|e| format!("{e}"))?;
        }
        Pc::Sa {
            nodal,
            nns,
            agg_levels,
        } => ksp.set_pc_box_for_tests(build_sa(*nodal, nns, *agg_levels)),
    }
    ksp.set_tolerances(1e-8, 0.0, 1e8, 20 * n);
    ksp.set_operators(a.clone(), None);
    let t0 = Instant::now();
    ksp.setup().map_err(|e| format!("setup: {e}"))?;
    let t1 = Instant::now();
    let mut x = vec![0.0; n];
    let stats = ksp.solve(b, &mut x).map_err(|e| format!("solve: {e}"))?;
    let t2 = Instant::now();
    let mut r = vec![0.0; n];
    a.matvec(&x, &mut r);
    let rn = r
        .iter()
        .zip(b)
        .map(|(p, q)| (p - q) * (p - q))
        .sum::<f64>()
        .sqrt();
    let bn = b.iter().map(|q| q * q).sum::<f64>().sqrt();
    Ok(Outcome {
        iters: stats.iterations,
        reason: format!("{:?}", stats.reason),
        setup_s: (t1 - t0).as_secs_f64(),
        solve_s: (t2 - t1).as_secs_f64(),
        relres: rn / bn,
    })
}

fn guarded(a: &Arc<dyn LinOp<S = f64>>, b: &[f64], pc: &Pc, norm: &str) -> Result<Outcome, String> {
    match catch_unwind(AssertUnwindSafe(|| run(a, b, pc, norm))) {
        Ok(r) => r,
        Err(p) => Err(format!(
            "panic: {}",
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default()
        )),
    }
}

fn main() {
    if let Ok(name) = std::env::var("AMG_EVAL_DIAG") {
        diagnose(&name);
        return;
    }
    let mut systems: Vec<(String, Vec<(&str, Pc)>)> = Vec::new();
    for side in [63, 127, 255] {
        systems.push((
            format!("membrane{side}"),
            vec![
                ("jacobi", Pc::Jacobi),
                ("amg-default", Pc::AmgDefault),
                (
                    "sa",
                    Pc::Sa {
                        nodal: false,
                        nns: None,
                        agg_levels: 0,
                    },
                ),
                (
                    "sa-mis2",
                    Pc::Sa {
                        nodal: false,
                        nns: None,
                        agg_levels: 25,
                    },
                ),
            ],
        ));
    }
    for n in [32, 64, 128] {
        let rbm = read_dense(&format!("data/elastic{n}_B.mtx"));
        systems.push((
            format!("elastic{n}"),
            vec![
                ("jacobi", Pc::Jacobi),
                ("amg-default", Pc::AmgDefault),
                (
                    "sa",
                    Pc::Sa {
                        nodal: false,
                        nns: None,
                        agg_levels: 0,
                    },
                ),
                (
                    "sa-nodal",
                    Pc::Sa {
                        nodal: true,
                        nns: None,
                        agg_levels: 0,
                    },
                ),
                (
                    "sa-nodal-rbm",
                    Pc::Sa {
                        nodal: true,
                        nns: Some(rbm.clone()),
                        agg_levels: 0,
                    },
                ),
                (
                    "sa-nodal-rbm-mis2",
                    Pc::Sa {
                        nodal: true,
                        nns: Some(rbm),
                        agg_levels: 25,
                    },
                ),
            ],
        ));
    }
    // `amg_eval SYSTEM CONFIG` runs one pair (run_kryst.sh does that, each under a time and
    // memory limit); without arguments every pair runs in this process.
    let args: Vec<String> = std::env::args().collect();
    let csv_path = "data/kryst_results.csv";
    let fresh = !std::path::Path::new(csv_path).exists();
    let mut csv = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(csv_path)
        .unwrap();
    if fresh {
        writeln!(
            csv,
            "system,N,config,iters,reason,setup_s,solve_s,relres,iters_prec_norm"
        )
        .unwrap();
    }
    println!(
        "{:<12}{:>7}  {:<13}{:>6}{:>9}{:>9}{:>10}{:>10}  reason",
        "system", "N", "config", "iters", "setup s", "solve s", "relres", "prec-norm"
    );
    for (name, configs) in &systems {
        if args.len() > 1 && &args[1] != name {
            continue;
        }
        let (n, t) = read_coo(&format!("data/{name}_A.mtx"));
        let b: Vec<f64> = read_dense(&format!("data/{name}_b.mtx")).remove(0);
        let a = to_op(n, t);
        for (label, pc) in configs {
            if args.len() > 2 && args[2] != *label {
                continue;
            }
            let main = guarded(&a, &b, pc, "unprecond");
            let prec = guarded(&a, &b, pc, "precond");
            let prec_iters = match &prec {
                Ok(o) => o.iters.to_string(),
                Err(_) => "failed".to_string(),
            };
            match main {
                Ok(o) => {
                    println!(
                        "{name:<12}{n:>7}  {label:<13}{:>6}{:>9.3}{:>9.3}{:>10.1e}{:>10}  {}",
                        o.iters, o.setup_s, o.solve_s, o.relres, prec_iters, o.reason
                    );
                    writeln!(
                        csv,
                        "{name},{n},{label},{},{},{:.4},{:.4},{:.2e},{prec_iters}",
                        o.iters, o.reason, o.setup_s, o.solve_s, o.relres
                    )
                    .unwrap();
                }
                Err(e) => {
                    println!("{name:<12}{n:>7}  {label:<13} FAILED: {e}");
                    writeln!(
                        csv,
                        "{name},{n},{label},,FAILED: {},,,,{prec_iters}",
                        e.replace(',', ";")
                    )
                    .unwrap();
                }
            }
        }
    }
}
