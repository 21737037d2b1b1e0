//! Prints a scene's steps one by one, for looking at a case the campaign found:
//! `cargo run --release -p hopsim-gen --example inspect -- SCENE.toml [FIRST] [LAST]`
//! shows, for each step from FIRST to LAST, the largest speed, the energy account and
//! every closed contact and stop with its percussions and velocities.

use hopsim_sim::{Simulation, StepView};
use std::path::Path;

fn show(v: &StepView<'_>) {
    let r = v.record;
    let speed = v.state.u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let e = &r.energy;
    println!(
        "step {} t={:.6} |u|max={speed:.4e} E={:.6e} contact_work={:.6e} lcp_failed={} res=({:.2e},{:.2e})",
        r.step, r.t, e.total(), e.contact_work, r.lcp_failed, r.resolution.velocity, r.resolution.impulse
    );
    for (c, pair) in r
        .contacts
        .iter()
        .map(|c| (c, false))
        .chain(r.pair_contacts.iter().map(|c| (c, true)))
    {
        let i = if pair {
            v.model.contacts().len() + c.contact
        } else {
            c.contact
        };
        let m = v.model.material(i);
        println!(
            "  {:<24} gap={:+.3e} ΛN={:.4e} ΛT={:+.4e} γA={:+.4e} ξN={:+.3e} ξT={:+.3e} W={:+.3e} {:?} μ={:.3} εN={:.3} εT={:.3}",
            v.model.contact_name(i), c.gap, c.impulse_normal, c.impulse_tangent, c.approach_velocity,
            c.normal_velocity, c.slip_velocity, c.work, c.state, m.friction, m.restitution_normal, m.restitution_tangent
        );
    }
    for l in &r.limits {
        println!(
            "  stop {:<19} gap={:+.3e} Λ={:.4e} γA={:+.4e} γE={:+.4e}",
            v.model.limits()[l.limit].name,
            l.gap,
            l.impulse,
            l.velocity_before,
            l.velocity_after
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = Path::new(&args[1]);
    let first: u64 = args.get(2).and_then(|v| v.parse().ok()).unwrap_or(1);
    let last: u64 = args
        .get(3)
        .and_then(|v| v.parse().ok())
        .unwrap_or(first + 10);
    let scene = hopsim_scene::load(path, &[]).unwrap_or_else(|e| panic!("{e}"));
    println!("coordinates: {:?}", scene.coordinates);
    let mut sim = Simulation::new(&scene);
    struct Show(u64, u64);
    impl hopsim_sim::Observer for Show {
        fn on_step(&mut self, v: &StepView<'_>) -> Result<(), hopsim_sim::RunError> {
            if (self.0..=self.1).contains(&v.record.step) {
                show(v);
            }
            Ok(())
        }
    }
    let mut observer = Show(first, last);
    for _ in 0..last {
        if let Err(e) = sim.step(&mut observer) {
            println!("stopped: {e}");
            break;
        }
    }
}
