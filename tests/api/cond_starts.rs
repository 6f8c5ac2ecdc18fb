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
