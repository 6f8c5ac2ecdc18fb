use penalty_lab::metrics::{self, MetricSet};
use penalty_lab::model::beam::paper;
use penalty_lab::strategy::{self, Method};
use penalty_lab::system::ConstraintKind;
fn main() {
    for kind in [ConstraintKind::Bilateral, ConstraintKind::Upper, ConstraintKind::Lower] {
    let p = paper::problem_with_kind(kind);
    for m in [Method::Paper{delta:0.1}, Method::Condensed{delta:0.1}, Method::Spring{delta:0.1}, Method::Constant{eps:1e6}, Method::Scaled{factor:100.0}, Method::Lagrange, Method::Augmented{eps:10.0, tol:1e-8, adaptive:false}, Method::Augmented{eps:10.0, tol:1e-8, adaptive:true}] {
        let s = strategy::solve(&p, m).unwrap();
        let mm = metrics::compute(&p, &s, MetricSet::ALL).unwrap();
        println!("{:?} {:?}\n  eps {:?}\n  gaps {:?}\n  cond {:.6} det {:?} stats {:?} w {:?}", kind, m, s.penalties, s.gaps, mm.cond2_system.unwrap().cond2, mm.log10_det_system, s.stats, s.warnings);
    }}
}
