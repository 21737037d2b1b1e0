//! Prints the scene of a MuJoCo model and checks it:
//! `cargo run --release -p hopsim-scene --example import_mjcf -- model.xml`.
fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: import_mjcf MODEL.xml");
        std::process::exit(2);
    };
    let path = std::path::Path::new(&path);
    match hopsim_scene::import_mjcf(path) {
        Ok(text) => print!("{text}"),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    }
    if let Err(e) = hopsim_scene::load(path, &[]) {
        eprintln!("scene: {e}");
        std::process::exit(1);
    }
}
