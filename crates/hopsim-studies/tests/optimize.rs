//! CMA-ES (`hopsim_studies::optimize`) against problems with known optima: shifted spheres
//! and Rosenbrock's function through the engine's function objective, a constrained and an
//! integer problem, and a projectile's launch (the range `2 v_x v_y / g` at a given energy is
//! largest at 45°) through scene runs; and a search stopped mid-way and resumed from its
//! checkpoint against the uninterrupted one, bit for bit.

use hopsim_scene::Scene;
use hopsim_studies::optimize::{
    read_checkpoint, run, Constraint, Direction, FunctionObjective, Objective, OptimizeReport,
    Outcome, Parameter, Problem, SceneObjective, Search, Stop,
};
use hopsim_studies::progress::Silent;
use hopsim_studies::sweep::RunDone;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

fn parameters(bounds: &[(f64, f64)]) -> Vec<Parameter> {
    (bounds.iter().enumerate())
        .map(|(i, &(lower, upper))| Parameter {
            key: format!("x{i}"),
            lower,
            upper,
            integer: false,
        })
        .collect()
}

fn problem(parameters: Vec<Parameter>, direction: Direction, generations: usize) -> Problem {
    Problem {
        parameters,
        direction,
        start: None,
        sigma: 0.3,
        population: None,
        seed: 7,
        max_generations: generations,
        objective: "test function".into(),
    }
}

fn search(problem: Problem, f: impl Fn(&[f64]) -> Outcome + Sync) -> OptimizeReport {
    let mut s = Search::new(problem).unwrap();
    run(&mut s, &FunctionObjective(f), &Silent, None, None).unwrap()
}

fn best(report: &OptimizeReport) -> (Vec<f64>, f64) {
    let b = report.best.as_ref().expect("an accepted point");
    (b.values.clone(), b.objective.unwrap())
}

/// `Σ (x_i − c_i)²`, minimum 0 at `c` (inside the bounds, away from their centre).
#[test]
fn finds_the_centre_of_shifted_spheres() {
    for dim in [2, 5] {
        let centre: Vec<f64> = (0..dim).map(|i| 1.7 - 0.9 * i as f64).collect();
        let c = centre.clone();
        let report = search(
            problem(
                parameters(&vec![(-5.0, 5.0); dim]),
                Direction::Minimize,
                300,
            ),
            move |x| Ok(x.iter().zip(&c).map(|(a, b)| (a - b).powi(2)).sum()),
        );
        let (x, f) = best(&report);
        assert!(f < 1e-10, "{dim} D: f = {f}");
        for (a, b) in x.iter().zip(&centre) {
            assert!((a - b).abs() < 1e-5, "{dim} D: {x:?} against {centre:?}");
        }
    }
}

/// Rosenbrock's function `Σ 100 (x_{i+1} − x_i²)² + (1 − x_i)²`, minimum 0 at `(1, …, 1)`,
/// at the end of a curved valley; 2 to 5 dimensions.
#[test]
fn finds_the_minimum_of_rosenbrock_in_2_to_5_dimensions() {
    let rosenbrock = |x: &[f64]| -> Outcome {
        Ok(x.windows(2)
            .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2))
            .sum())
    };
    for dim in 2..=5 {
        let report = search(
            problem(
                parameters(&vec![(-2.0, 3.0); dim]),
                Direction::Minimize,
                1500,
            ),
            rosenbrock,
        );
        let (x, f) = best(&report);
        assert!(f < 1e-8, "{dim} D: f = {f} at {x:?}");
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-3), "{dim} D: {x:?}");
    }
}

/// Maximising `−(x − 0.8)²` with every point `x > 0.5` rejected: the constrained maximum
/// is at the bound 0.5; rejections are recorded with their reason and never the best.
#[test]
fn rejected_points_are_recorded_and_the_constrained_optimum_found() {
    let report = search(
        problem(parameters(&[(-2.0, 2.0)]), Direction::Maximize, 80),
        |x| {
            if x[0] > 0.5 {
                Err(format!("x = {} > 0.5", x[0]))
            } else {
                Ok(-(x[0] - 0.8).powi(2))
            }
        },
    );
    let (x, _) = best(&report);
    assert!(
        x[0] <= 0.5 && x[0] > 0.5 - 1e-4,
        "{x:?} after {} generations, {:?}",
        report.generations.len(),
        report.stop
    );
    assert!(report.rejected > 0);
    let rejected = report
        .generations
        .iter()
        .flatten()
        .filter(|e| e.objective.is_none());
    for e in rejected {
        assert!(e.values[0] > 0.5);
        assert!(e.error.as_deref().unwrap().contains("> 0.5"));
    }
    let csv = report.table().to_csv_string();
    assert!(
        csv.lines()
            .any(|l| l.contains(",rejected,") && l.contains("> 0.5")),
        "{csv}"
    );
}

/// A whole-number parameter is evaluated at whole numbers only: `(n − 3.3)²` is least at 3.
#[test]
fn integer_parameters_take_whole_numbers() {
    let mut params = parameters(&[(-10.0, 10.0), (-1.0, 1.0)]);
    params[0].integer = true;
    let report = search(problem(params, Direction::Minimize, 60), |x| {
        Ok((x[0] - 3.3).powi(2) + x[1] * x[1])
    });
    assert!(report
        .generations
        .iter()
        .flatten()
        .all(|e| e.values[0] == e.values[0].round()));
    let (x, _) = best(&report);
    assert_eq!(x[0], 3.0);
}

/// The same seed gives the same search; another seed another one.
#[test]
fn the_seed_makes_the_search() {
    let f = |x: &[f64]| -> Outcome { Ok(x[0].powi(2) + (x[1] - 1.0).powi(2)) };
    let p = problem(parameters(&[(-3.0, 3.0); 2]), Direction::Minimize, 5);
    let a = search(p.clone(), f);
    let b = search(p.clone(), f);
    let c = search(Problem { seed: 8, ..p }, f);
    assert_eq!(a.generations, b.generations);
    assert_ne!(a.generations, c.generations);
}

/// An objective that sets `stop` once `after` points have been evaluated: the search is
/// stopped in the generation under way, as a killed process would be.
struct StopsAfter<F> {
    f: F,
    after: usize,
    count: AtomicUsize,
    stop: AtomicBool,
}

impl<F: Fn(&[f64]) -> Outcome + Sync> Objective for StopsAfter<F> {
    fn evaluate(&self, points: &[Vec<f64>], done: RunDone<'_>) -> Vec<Outcome> {
        (points.iter())
            .map(|p| {
                if self.count.fetch_add(1, Ordering::SeqCst) + 1 >= self.after {
                    self.stop.store(true, Ordering::SeqCst);
                }
                done();
                (self.f)(p)
            })
            .collect()
    }
}

/// A search stopped in its 5th generation keeps 4 in its checkpoint; resumed from the
/// file it gives every evaluation of the uninterrupted search, bit for bit.
#[test]
fn a_resumed_search_is_the_uninterrupted_one() {
    let f = |x: &[f64]| -> Outcome {
        let r: f64 = x
            .windows(2)
            .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2))
            .sum();
        if x[0] < -1.5 {
            return Err("rejected".into());
        }
        Ok(r + (1.0 - x[0]).powi(2))
    };
    let p = problem(parameters(&[(-2.0, 2.0); 3]), Direction::Minimize, 12);
    let whole = search(p.clone(), f);
    assert_eq!(whole.generations.len(), 12);

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    let lambda = p.population();
    let stopping = StopsAfter {
        f,
        after: 4 * lambda + 2,
        count: AtomicUsize::new(0),
        stop: AtomicBool::new(false),
    };
    let mut first = Search::new(p).unwrap();
    let part = run(
        &mut first,
        &stopping,
        &Silent,
        Some(&path),
        Some(&stopping.stop),
    )
    .unwrap();
    assert_eq!(part.stop, None, "interrupted");
    let saved = read_checkpoint(&path).unwrap();
    assert_eq!(
        saved.generations.len(),
        4,
        "the generation under way is lost"
    );
    assert_eq!(saved.generations[..], whole.generations[..4]);

    let mut resumed = Search::resume(saved).unwrap();
    let rest = run(
        &mut resumed,
        &FunctionObjective(f),
        &Silent,
        Some(&path),
        None,
    )
    .unwrap();
    assert_eq!(rest.generations, whole.generations);
    assert_eq!(rest.best, whole.best);
    assert_eq!(rest.stop, Some(Stop::MaxGenerations));
    assert_eq!(
        read_checkpoint(&path).unwrap().generations,
        whole.generations
    );
}

/// A finished search of 5 generations, resumed for 9, gives the evaluations of a search
/// planned for 9 from the start; resumed for 3 it has ended, with its 5 kept.
#[test]
fn a_finished_search_extends_to_the_longer_one() {
    let f = |x: &[f64]| -> Outcome { Ok((x[0] - 0.3).powi(2) + x[1].abs()) };
    let p = problem(parameters(&[(-2.0, 2.0); 2]), Direction::Minimize, 5);
    let short = search(p.clone(), f);
    assert_eq!(short.stop, Some(Stop::MaxGenerations));
    let long = search(
        Problem {
            max_generations: 9,
            ..p.clone()
        },
        f,
    );
    let mut finished = Search::new(p.clone()).unwrap();
    run(&mut finished, &FunctionObjective(f), &Silent, None, None).unwrap();
    let saved = finished.checkpoint();
    assert!(saved.problem.same_search(&Problem {
        max_generations: 9,
        ..p.clone()
    }));
    assert!(!saved.problem.same_search(&Problem {
        seed: 8,
        ..p.clone()
    }));

    let mut extended = Search::resume(saved.clone())
        .unwrap()
        .with_max_generations(9)
        .unwrap();
    let rest = run(&mut extended, &FunctionObjective(f), &Silent, None, None).unwrap();
    assert_eq!(rest.generations, long.generations);
    assert_eq!(rest.best, long.best);

    let mut ended = Search::resume(saved)
        .unwrap()
        .with_max_generations(3)
        .unwrap();
    assert_eq!(ended.ask().unwrap(), None);
    assert_eq!(ended.stopped(), Some(&Stop::MaxGenerations));
    assert_eq!(ended.generations(), &short.generations[..]);
    assert!(Search::new(p).unwrap().with_max_generations(0).is_err());
}

/// A checkpoint of another search (another seed) is refused when it is resumed.
#[test]
fn a_checkpoint_of_another_search_is_refused() {
    let f = |x: &[f64]| -> Outcome { Ok(x[0] * x[0]) };
    let p = problem(parameters(&[(-1.0, 1.0)]), Direction::Minimize, 3);
    let mut s = Search::new(p).unwrap();
    run(&mut s, &FunctionObjective(f), &Silent, None, None).unwrap();
    let mut c = s.checkpoint();
    c.problem.seed += 1;
    let e = Search::resume(c).unwrap_err().to_string();
    assert!(e.contains("does not replay"), "{e}");
}

/// A point mass launched from the ground with `(v_x, v_y)` lands `2 v_x v_y / g` ahead and
/// sticks (`tests/data/optimize/projectile.toml`: restitution 0, friction 5 ≥ cot of every
/// launch angle above 11°): its range at
/// a kinetic energy of at most `E = 2 J` (the landing dissipates it all) is largest at 45°,
/// `v_x = v_y = √E`, `R = 2E/(m g)`. The energy bound is a constraint on the run summary.
#[test]
fn finds_the_launch_angle_of_the_longest_throw() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/optimize/projectile.toml");
    let scene: Scene = hopsim_scene::load(&path, &[]).unwrap();
    let (energy, g) = (2.0, 9.81);
    let objective = SceneObjective {
        scene: &scene,
        base: Vec::new(),
        keys: vec!["initial.u.0".into(), "initial.u.1".into()],
        field: "distance_m".into(),
        constraints: vec![Constraint {
            field: "energy.dissipated".into(),
            lower: None,
            upper: Some(energy),
        }],
        stop: None,
    };
    let mut params = parameters(&[(0.0, 2.5), (0.0, 2.5)]);
    params[0].key = "initial.u.0".into();
    params[1].key = "initial.u.1".into();
    let mut s = Search::new(Problem {
        population: Some(8),
        ..problem(params, Direction::Maximize, 40)
    })
    .unwrap();
    let report = run(&mut s, &objective, &Silent, None, None).unwrap();
    let (v, range) = best(&report);
    let angle = v[1].atan2(v[0]).to_degrees();
    let best_range = 2.0 * energy / g;
    assert!((angle - 45.0).abs() < 2.0, "launch angle {angle}° at {v:?}");
    assert!(
        (range / best_range - 1.0).abs() < 2e-3,
        "range {range} m against {best_range} m"
    );
    assert!(report.rejected > 0, "the energy bound was met and rejected");
}
