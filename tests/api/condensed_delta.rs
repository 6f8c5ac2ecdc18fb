//! `condensed` never ends above δ: the max penetration recomputed from the returned u is ≤ δ
//! in floating point (no tolerance), on the sweep's scene families — dense beams, sparse beams
//! (> 150 elements), 5-point membranes on the dense route and on the sparse elimination route
//! (n ≥ 2000), SPD spectra — at δ = 1e-1, 1e-4 and 1e-6 of the displacement scale, where the
//! error of g0 − g* grows like |g0|/δ. Penalized constraints sit within 1e-6·δ of δ, or the
//! solution says (in a warning) how close rounding let them get.

use penalty_lab::generate::{generate, Family, GeneratorConfig};
use penalty_lab::strategy::{self, Method};

#[test]
fn condensed_penetration_never_exceeds_delta_on_the_sweep_families() {
    let cfg = GeneratorConfig {
        beam_elements: (3, 400),
        membrane_side: (10, 50),
        spectrum_n: (20, 80),
        spectrum_log10_spread: (2.0, 10.0),
        elastic_h: (0.1, 0.25),
    };
    let (mut rows, mut penalized, mut far) = (0, 0, 0);
    for family in [Family::Beam, Family::Membrane, Family::Spectrum] {
        for index in 0..8 {
            let sc = generate(family, index, 11, &cfg).unwrap();
            let p = &sc.problem;
            let u0 = strategy::Prepared::new(p).unwrap().u0().to_vec();
            let scale = p
                .constraints
                .iter()
                .map(|c| u0[c.single_dof().unwrap()].abs())
                .fold(0.0, f64::max);
            for rel in [1e-1, 1e-4, 1e-6] {
                let delta = rel * scale;
                let s = strategy::solve(p, Method::condensed(delta)).unwrap();
                rows += 1;
                let tag = format!("{} δ = {rel}·|u0| (n = {})", sc.name, p.n());
                assert!(s.stats.converged, "{tag}");
                let pen = p.penetrations(&s.u);
                for (c, &pc) in pen.iter().enumerate() {
                    assert!(
                        pc <= delta,
                        "{tag}: c = {c}: penetration {pc:e} > δ = {delta:e}"
                    );
                }
                assert!(s.max_penetration <= delta, "{tag}");
                let worst = s
                    .penalties
                    .iter()
                    .zip(&pen)
                    .filter(|(&e, _)| e > 0.0)
                    .map(|(_, &pc)| (delta - pc) / delta)
                    .fold(0.0f64, f64::max);
                penalized += usize::from(s.penalties.iter().any(|&e| e > 0.0));
                if worst > 1e-6 {
                    far += 1;
                    assert!(
                        s.warnings
                            .iter()
                            .any(|w| w.contains("rounding of the gaps")),
                        "{tag}: penalized gap {worst:.1e}·δ from δ without a warning"
                    );
                }
            }
        }
    }
    eprintln!("{rows} rows, {penalized} with penalties, {far} further than 1e-6·δ from δ");
    assert!(
        penalized >= rows / 2,
        "too few penalized rows: {penalized} of {rows}"
    );
}
