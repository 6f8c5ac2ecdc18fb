//! The bottom start a sweep gives its penalized rows (`metrics::contact_bottom`: K_ℱℱ's bottom
//! Ritz vector at the exact contact set) is used where the contact set is known: on a
//! membrane at a large penalty the system's cond₂ then takes fewer Lanczos steps than from
//! K's vectors alone, inside the same certified bracket; and the vector is refused where it
//! cannot be formed.

use penalty_lab::generate::{generate, Family, GeneratorConfig};
use penalty_lab::metrics::{self, MetricSet};
use penalty_lab::strategy::{self, Method};

#[test]
fn the_contact_set_start_saves_steps_on_a_membrane() {
    let cfg = GeneratorConfig {
        membrane_side: (17, 17),
        ..GeneratorConfig::default()
    };
    let sc = generate(Family::Membrane, 0, 5, &cfg).unwrap();
    let p = &sc.problem;
    let contact = strategy::solve(p, Method::lagrange())
        .unwrap()
        .contact_set()
        .expect("a contact set");
    let sol = strategy::solve(p, Method::constant(1e8)).unwrap();
    let set = MetricSet {
        cond: true,
        ..MetricSet::default()
    };
    let plain = metrics::compute(p, &sol, set).unwrap();
    let started = metrics::compute_at_contact_set(p, &sol, set, Some(&contact)).unwrap();
    let (plain, started) = (
        plain.cond2_system.expect("cond₂"),
        started.cond2_system.expect("cond₂"),
    );
    let steps = |r: &penalty_lab::conditioning::CondReport| r.certificate.unwrap().lanczos_steps;
    assert!(
        steps(&started) < steps(&plain),
        "{} vs {}",
        steps(&started),
        steps(&plain)
    );
    for (x, y) in [(&plain, &started), (&started, &plain)] {
        assert!(x.within_contract() && x.cond2_lo <= y.cond2 && y.cond2 <= x.cond2_hi);
    }
    // No vector without a constraint in contact, with every DOF in contact, or with a contact
    // set naming a constraint the problem does not have.
    let (_, ritz) = penalty_lab::conditioning::cond2_warm(
        &p.k,
        penalty_lab::conditioning::Reuse::keeping_ritz(),
    )
    .unwrap();
    let ritz = ritz.expect("K's Ritz vectors");
    assert!(metrics::contact_bottom(p, &contact, &ritz).is_some());
    assert!(metrics::contact_bottom(p, &vec![false; contact.len()], &ritz).is_none());
    let mut too_long = contact.clone();
    too_long.push(true);
    assert!(metrics::contact_bottom(p, &too_long, &ritz).is_none());
}

/// A penalized solve hands its final `K + D E Dᵀ` to the metrics (`Solution::matrix`) only
/// where that matrix is symmetric bit for bit — K exactly symmetric and every penalized
/// constraint single-DOF — and it is then the matrix the metrics would assemble, with the same
/// cond₂ bit for bit; a K one unit off symmetric or a coupled row gets no matrix.
#[test]
fn the_solve_hands_on_its_matrix_only_where_it_is_exactly_symmetric() {
    use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
    let cfg = GeneratorConfig {
        membrane_side: (12, 12),
        ..GeneratorConfig::default()
    };
    let p = generate(Family::Membrane, 0, 5, &cfg).unwrap().problem;
    assert!(p.k.is_sparse() && p.k.is_symmetric());
    let set = MetricSet {
        cond: true,
        det: true,
        ..MetricSet::default()
    };
    let sol = strategy::solve(&p, Method::constant(1e4)).unwrap();
    let handed = sol
        .matrix
        .as_deref()
        .expect("an exactly symmetric system is handed on");
    assert!(handed.is_symmetric());
    assert_eq!(
        handed.to_dense(),
        metrics::system_matrix(&p, &sol).to_dense()
    );
    let mut bare = sol.clone();
    bare.matrix = None;
    let (with, without) = (
        metrics::compute(&p, &sol, set).unwrap(),
        metrics::compute(&p, &bare, set).unwrap(),
    );
    let (a, b) = (with.cond2_system.unwrap(), without.cond2_system.unwrap());
    assert_eq!(
        (
            a.cond2.to_bits(),
            a.cond2_lo.to_bits(),
            a.cond2_hi.to_bits()
        ),
        (
            b.cond2.to_bits(),
            b.cond2_lo.to_bits(),
            b.cond2_hi.to_bits()
        )
    );
    assert_eq!(with.log10_det_system, without.log10_det_system);

    // K one unit in the last place off symmetric (in the first off-diagonal entry).
    let mut entries = Vec::new();
    p.k.for_each_entry(|i, j, v| entries.push((i, j, v)));
    let at = entries.iter().position(|&(i, j, _)| i > j).unwrap();
    entries[at].2 = f64::from_bits(entries[at].2.to_bits() + 1);
    let near = Stiffness::from_triplets(p.n(), &entries).unwrap();
    assert!(!near.is_symmetric());
    let pn = Problem::new(near, p.q.clone(), p.constraints.clone()).unwrap();
    let sol = strategy::solve(&pn, Method::constant(1e4)).unwrap();
    assert!(sol.matrix.is_none());

    // A (bilateral, so always penalized) row coupling two DOFs adds off-diagonal entries.
    let mut rows = p.constraints.clone();
    let (d0, d1) = (rows[0].lead_dof(), rows[1].lead_dof());
    rows[0] = Constraint::row(vec![(d0, 0.6), (d1, 0.8)], 0.0, ConstraintKind::Bilateral);
    let pc = Problem::new(p.k.clone(), p.q.clone(), rows).unwrap();
    let sol = strategy::solve(&pc, Method::constant(1e4)).unwrap();
    assert!(sol.penalties[0] != 0.0 && sol.factor.is_some());
    assert!(sol.matrix.is_none());
}
