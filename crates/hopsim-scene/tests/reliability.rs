//! The scene reader on hostile input: endless or binary files, scenes too large for the
//! model's dense matrices, values that only overflow later, and `--set` overrides whose
//! errors must name the override rather than the scene file.

use hopsim_scene::{Override, MAX_BODIES, MAX_DEPTH, MAX_SCENE_BYTES};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Bytes currently allocated, and the peak since the last reset.
static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// Tests measuring `PEAK` run one at a time.
static MEASURE: Mutex<()> = Mutex::new(());

struct Peak;

// SAFETY: forwards to the system allocator, only counting bytes.
unsafe impl GlobalAlloc for Peak {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let now = CURRENT.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
        PEAK.fetch_max(now, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size >= layout.size() {
            let grow = new_size - layout.size();
            let now = CURRENT.fetch_add(grow, Ordering::Relaxed) + grow;
            PEAK.fetch_max(now, Ordering::Relaxed);
        } else {
            CURRENT.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Peak = Peak;

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn robbit(overrides: &[&str]) -> Result<hopsim_scene::Scene, String> {
    let overrides: Vec<Override> = overrides.iter().map(|o| o.parse().unwrap()).collect();
    hopsim_scene::load(&repo("scenes/robbit.toml"), &overrides).map_err(|e| e.to_string())
}

fn robbit_error(overrides: &[&str]) -> String {
    match robbit(overrides) {
        Ok(_) => panic!("{overrides:?} loaded without error"),
        Err(e) => e,
    }
}

// ---- bounded reads -------------------------------------------------------------------

#[test]
fn endless_and_binary_inputs_are_refused_at_once() {
    for dev in ["/dev/zero", "/dev/urandom"] {
        if !Path::new(dev).exists() {
            continue;
        }
        let start = Instant::now();
        let e = hopsim_scene::load(Path::new(dev), &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(&format!("{dev}: not a text file (NUL byte at offset ")),
            "{e}"
        );
        assert!(start.elapsed() < Duration::from_secs(5));
    }
}

#[test]
fn a_file_above_the_size_limit_is_refused_unread() {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hopsim_scene_huge.toml");
    let file = std::fs::File::create(&path).unwrap();
    file.set_len(MAX_SCENE_BYTES + 1).unwrap(); // sparse: costs no disk
    drop(file);
    let e = hopsim_scene::load(&path, &[]).unwrap_err().to_string();
    std::fs::remove_file(&path).unwrap();
    assert!(
        e.ends_with(
            "hopsim_scene_huge.toml: the file is larger than the 8 MiB limit of scene files"
        ),
        "{e}"
    );
}

// ---- scenes too large for the model --------------------------------------------------

/// A valid scene text with `count` bodies in a chain, each hanging on the previous one.
fn chain_scene(count: usize) -> String {
    let mut s = String::from(
        "[simulation]\nduration = 1.0\ndt = 1e-3\n\n[[bodies]]\nname = \"b0\"\nmass = 1.0\n\
         inertia = 1e-3\n",
    );
    for i in 1..count {
        s.push_str(&format!(
            "\n[[bodies]]\nname = \"b{i}\"\nparent = \"b{}\"\nmass = 0.1\ninertia = 1e-4\n",
            i - 1
        ));
    }
    s.push_str("\n[[shapes]]\nbody = \"b0\"\ntype = \"circle\"\nradius = 0.2\n\n[initial]\nq = [");
    let q: Vec<&str> = std::iter::once("0.0")
        .chain(std::iter::once("0.5"))
        .chain(std::iter::repeat_n("0.0", count))
        .collect();
    s.push_str(&q.join(", "));
    s.push_str("]\n");
    s
}

/// The result of parsing `text` and the peak heap use meanwhile, bytes.
fn parse_with_peak(text: &str) -> (Result<hopsim_scene::Scene, String>, usize) {
    let _one = MEASURE.lock().unwrap_or_else(|e| e.into_inner());
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let result = hopsim_scene::parse(text, Path::new("chain.toml"), &[]).map_err(|e| e.to_string());
    let peak = PEAK.load(Ordering::Relaxed) - base;
    (result, peak)
}

#[test]
fn twenty_thousand_bodies_are_refused_without_allocating_gigabytes() {
    let text = chain_scene(20_000);
    assert!(text.len() > 1_000_000, "{} bytes", text.len());
    let start = Instant::now();
    let (result, peak) = parse_with_peak(&text);
    let e = result.unwrap_err();
    assert!(
        e.starts_with("chain.toml:")
            && e.contains(&format!(
                "bodies[{MAX_BODIES}]: a scene may have at most {MAX_BODIES} bodies"
            ))
            && e.ends_with("found 20000"),
        "{e}"
    );
    assert!(peak < 256 << 20, "peak heap {} MB", peak >> 20);
    assert!(start.elapsed() < Duration::from_secs(20));
}

#[test]
fn the_largest_accepted_scene_loads_in_bounded_memory() {
    let (result, peak) = parse_with_peak(&chain_scene(MAX_BODIES));
    let scene = result.unwrap();
    assert_eq!(scene.model.bodies().len(), MAX_BODIES);
    assert!(peak < 256 << 20, "peak heap {} MB", peak >> 20);
}

#[test]
fn shapes_with_too_many_contacts_are_refused_at_the_shape() {
    // A regular 1001-gon on flat ground: one contact per vertex, one too many.
    let vertices: Vec<String> = (0..1001)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 1001.0;
            format!("[{:?}, {:?}]", 0.1 * a.cos(), 0.1 * a.sin())
        })
        .collect();
    let text = format!(
        "[simulation]\nduration = 1.0\ndt = 1e-3\n\n[[bodies]]\nname = \"b0\"\nmass = 1.0\n\
         inertia = 1e-3\n\n[[shapes]]\nbody = \"b0\"\ntype = \"circle\"\nradius = 0.1\n\n\
         [[shapes]]\nbody = \"b0\"\ntype = \"polygon\"\nvertices = [{}]\n\n[initial]\n\
         q = [0.0, 0.5, 0.0]\n",
        vertices.join(", ")
    );
    let e = hopsim_scene::parse(&text, Path::new("many.toml"), &[])
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("many.toml:15:1: shapes[1]: the shapes make 1002 potential contacts"),
        "{e}"
    );
}

#[test]
fn deeply_nested_values_are_refused_not_a_stack_overflow() {
    for depth in [MAX_DEPTH + 2, 10_000] {
        let text = format!("x = {}1{}\n", "[".repeat(depth), "]".repeat(depth));
        let e = hopsim_scene::parse(&text, Path::new("deep.toml"), &[])
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("deep.toml:1:"), "{e}");
    }
    // Dotted keys nest tables too.
    let key: Vec<String> = (0..5_000).map(|i| format!("k{i}")).collect();
    let text = format!("{} = 1\n", key.join("."));
    let e = hopsim_scene::parse(&text, Path::new("deep.toml"), &[])
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("deep.toml:"), "{e}");
}

// ---- overrides -----------------------------------------------------------------------

#[test]
fn a_duplicate_made_by_an_override_names_the_override() {
    let e = robbit_error(&["bodies.disc.name=flywheel"]);
    // The file's own `name = "flywheel"` line (1-based), value at column 8.
    let text = std::fs::read_to_string(repo("scenes/robbit.toml")).unwrap();
    let line = 1 + text
        .lines()
        .position(|l| l.starts_with("name = \"flywheel\""))
        .unwrap();
    assert!(
        e.starts_with(
            "--set bodies.disc.name=flywheel: bodies[0].name: a body named 'flywheel' already \
             exists at "
        ) && e.ends_with(&format!(
            "robbit.toml:{line}:8 (bodies[1].name); names must be unique"
        )),
        "{e}"
    );
}

#[test]
fn a_name_an_override_changed_is_named_where_the_file_refers_to_it() {
    let e = robbit_error(&["bodies.disc.name=wheel"]);
    assert!(
        e.contains("bodies[1].parent: there is no body named 'disc'")
            && e.ends_with("(--set bodies.disc.name=wheel changed bodies[0].name)"),
        "{e}"
    );
    let e = robbit_error(&["bodies.flywheel.name=rotor"]);
    assert!(
        e.contains(
            "controller.flywheel: there is no body named 'flywheel'; the bodies are: disc, \
             rotor (--set bodies.flywheel.name=rotor changed bodies[1].name)"
        ),
        "{e}"
    );
}

#[test]
fn an_override_replacing_a_table_by_a_value_is_blamed_not_the_next_option() {
    let overrides = [
        Override::new("simulation", "1"),
        Override::from_flag("--duration", "simulation.duration", "0.1"),
    ];
    let e = hopsim_scene::load(&repo("scenes/robbit.toml"), &overrides)
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "--set simulation=1: 'simulation' is a table in the scene and cannot be replaced by \
         the integer 1; set its keys instead, e.g. --set simulation.dt=…"
    );
    let e = robbit_error(&["bodies=3"]);
    assert!(
        e.starts_with("--set bodies=3: 'bodies' is an array of tables in the scene"),
        "{e}"
    );
    let e = robbit_error(&["bodies.0=3"]);
    assert!(
        e.starts_with("--set bodies.0=3: 'bodies.0' is a table"),
        "{e}"
    );
    // A value set by one override, walked into by another, names the first.
    let e = robbit_error(&["controller.torque=1", "controller.torque.x=2"]);
    assert!(
        e.contains("(set by --set controller.torque=1), not a table"),
        "{e}"
    );
}

#[test]
fn numbers_in_messages_are_short() {
    let e = robbit_error(&["environment.restitution=1e308"]);
    assert_eq!(
        e,
        "--set environment.restitution=1e308: environment.restitution: expected a number in \
         [0, 1], found the number 1e308"
    );
    let e = robbit_error(&["simulation.dt=1e300"]);
    assert!(e.contains("found the number 1e300"), "{e}");
    assert!(e.len() < 200, "{e}");
}

#[test]
fn states_and_parameters_that_would_overflow_are_rejected_at_the_override() {
    let cases = [
        (
            "initial.q.1=1e308",
            "--set initial.q.1=1e308: initial.q[1]: expected a finite number in m or rad of \
             magnitude at most 1000000, found the number 1e308",
        ),
        (
            "initial.u.3=1e5",
            "--set initial.u.3=1e5: initial.u[3]: expected a finite number in m/s or rad/s of \
             magnitude at most 10000, found the number 100000",
        ),
        (
            "summary.speed_window=1e-308",
            "--set summary.speed_window=1e-308: summary.speed_window: the speed window 1e-308 s \
             is shorter than the step size 0.0002 s; expected at least one step",
        ),
        (
            "bodies.disc.mass=1e300",
            "--set bodies.disc.mass=1e300: bodies[0].mass: expected a positive number in kg of \
             magnitude at most 1000000000, found the number 1e300",
        ),
        (
            "simulation.dt=1e-300",
            "--set simulation.dt=1e-300: simulation.dt: expected a positive number in s of \
             magnitude at least 1e-9, found the number 1e-300",
        ),
        (
            "shapes.disc.radius=1e7",
            "--set shapes.disc.radius=1e7: shapes[0].radius: expected a positive number in m of \
             magnitude at most 1000000, found the number 10000000",
        ),
        (
            "simulation.duration=inf",
            "--set simulation.duration=inf: simulation.duration: expected a positive number in \
             s, found the number inf",
        ),
    ];
    for (set, expected) in cases {
        assert_eq!(robbit_error(&[set]), expected, "{set}");
    }
    // Large but sane values still load.
    let s = robbit(&[
        "initial.q.0=1e5",
        "initial.u.3=9999",
        "summary.speed_window=2e-4",
    ])
    .unwrap();
    assert_eq!(s.initial.q[0], 1e5);
}

/// `check_state` holds a state set after loading to the bounds the reader holds
/// `[initial]` to: what an override cannot start from, no state can be set to.
#[test]
fn a_state_set_later_is_checked_as_a_start_is() {
    use hopsim_scene::{check_state, StateProblem};
    let scene = robbit(&[]).unwrap();
    let with = |q1: f64, u3: f64, t: f64| {
        let mut state = scene.initial.clone();
        (state.q[1], state.u[3], state.t) = (q1, u3, t);
        check_state(&scene, &state)
    };
    let y = scene.initial.q[1];
    for (q1, u3, t, set) in [
        (1e308, 0.0, 0.0, "initial.q.1=1e308"),
        (f64::NAN, 0.0, 0.0, "initial.q.1=nan"),
        (y, 1e5, 0.0, "initial.u.3=1e5"),
    ] {
        let Err(StateProblem::Value { expected, .. }) = with(q1, u3, t) else {
            panic!("{set}: accepted");
        };
        let loader = robbit_error(&[set]);
        assert!(loader.contains(&format!("expected {expected}")), "{loader}");
    }
    let Err(StateProblem::Value { name, .. }) = with(y, 0.0, -1e300) else {
        panic!("t = -1e300 accepted");
    };
    assert_eq!(name, "t");
    assert_eq!(
        with(y, 0.0, f64::INFINITY).unwrap_err().to_string(),
        "t = inf: expected a finite number in s"
    );
    // The largest values a scene accepts, accepted.
    assert_eq!(with(1e5, 9999.0, 1e9), Ok(()));
    let mut short = scene.initial.clone();
    short.q = short.q.rows(0, 3).into_owned();
    assert_eq!(
        check_state(&scene, &short).unwrap_err().to_string(),
        "q and u must have 4 entries (x, y, phi, psi), got 3 and 4"
    );
}

/// A run is bounded by the steps it takes, `round(duration / dt)`: ten steps of 0.3 ms
/// (0.003 / 3e-4 = 10.000000000000002 in floating point) fit `max_steps = 10`.
#[test]
fn max_steps_bounds_the_steps_a_run_takes() {
    let set = |max: &str| {
        robbit(&[
            "simulation.dt=3e-4",
            "simulation.duration=0.003",
            &format!("simulation.max_steps={max}"),
        ])
    };
    assert_eq!(set("10").unwrap().settings.max_steps, 10);
    let e = set("9").unwrap_err();
    assert!(
        e.contains("0.003 s in steps of 0.0003 s is 10 steps, more than simulation.max_steps = 9"),
        "{e}"
    );
    assert_eq!(hopsim_scene::check_steps(0.003, 3e-4, 10), Ok(()));
}

#[test]
fn a_default_speed_window_never_falls_below_a_step() {
    // No [summary]: the window defaults to half the run, but never less than a step.
    let overrides = [Override::new("simulation.dt", "0.6")];
    let s = hopsim_scene::parse(&chain_scene(1), Path::new("chain.toml"), &overrides).unwrap();
    assert_eq!((s.settings.duration, s.settings.speed_window), (1.0, 0.6));
}

#[test]
fn names_that_break_csv_files_are_rejected_where_they_are_written() {
    let e = robbit_error(&["bodies.flywheel.name=\"a,b\""]);
    assert!(
        e.starts_with(
            "--set bodies.flywheel.name=\"a,b\": bodies[1].name: expected a name without commas"
        ),
        "{e}"
    );
    let e = robbit_error(&["bodies.flywheel.name=\"  \""]);
    assert!(e.contains("expected a non-empty name"), "{e}");
}
