fn main() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robbit.toml");
    let scene = hopsim_scene::load(&path, &[]).unwrap();
    let t = std::time::Instant::now();
    let mut hops = 0;
    for _ in 0..10 {
        hops += hopsim_sim::run(&scene, &mut ()).unwrap().hops;
    }
    println!("{hops} {:?}", t.elapsed() / 10);
}
