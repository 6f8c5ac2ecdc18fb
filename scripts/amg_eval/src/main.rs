use kryst::context::ksp_context::{KspContext, SolverType};
use kryst::context::pc_context::PcType;
use kryst::matrix::csr::CsrMatrix;
use kryst::matrix::op::{GenericCsrOp, LinOp};
use kryst::matrix::spmv::plan::SpmvTuning;
use std::sync::Arc;
use std::time::Instant;

fn read_coo(path: &str) -> (usize, Vec<(usize, usize, f64)>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('%'));
    let head: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    let t = lines
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

fn read_vec(path: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('%'))
        .skip(1)
        .map(|l| l.trim().parse().unwrap())
        .collect()
}

fn main() {
    for side in [63, 127, 255] {
        let (n, mut t) = read_coo(&format!("data/membrane{side}_A.mtx"));
        let b = read_vec(&format!("data/membrane{side}_b.mtx"));
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
        let a: Arc<dyn LinOp<S = f64>> = Arc::new(GenericCsrOp::new(csr, &SpmvTuning::default()));
        for pc in [PcType::Jacobi, PcType::Amg] {
            let mut ksp = KspContext::new();
            ksp.set_type(SolverType::Cg).unwrap();
            ksp.set_pc_type(pc, None).unwrap();
            ksp.set_tolerances(1e-8, 0.0, 1e8, 10 * n);
            ksp.set_operators(a.clone(), None);
            let t0 = Instant::now();
            ksp.setup().unwrap();
            let t1 = Instant::now();
            let mut x = vec![0.0; n];
            let stats = ksp.solve(&b, &mut x).unwrap();
            let t2 = Instant::now();
            let mut r = vec![0.0; n];
            a.matvec(&x, &mut r);
            let rn = r
                .iter()
                .zip(&b)
                .map(|(p, q)| (p - q) * (p - q))
                .sum::<f64>()
                .sqrt();
            let bn = b.iter().map(|q| q * q).sum::<f64>().sqrt();
            println!(
                "{side} n={n} {pc:?}: iterations {} converged {:?} setup {:.3} s solve {:.3} s relres {:.2e}",
                stats.iterations,
                stats.reason,
                (t1 - t0).as_secs_f64(),
                (t2 - t1).as_secs_f64(),
                rn / bn
            );
        }
    }
}
