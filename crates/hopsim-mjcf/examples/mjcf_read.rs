//! Reads an MJCF file and prints its planar model and notices:
//! `cargo run --release -p hopsim-mjcf --example mjcf_read -- model.xml [--unmodelled]`.

fn main() {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: mjcf_read MODEL.xml [--unmodelled]");
        std::process::exit(2);
    };
    let options = hopsim_mjcf::ReadOptions {
        unmodelled: args.any(|a| a == "--unmodelled"),
    };
    match hopsim_mjcf::read_file(&path, &options) {
        Ok(model) => {
            for n in &model.notices {
                println!("notice: {n}");
            }
            println!(
                "plane: normal {:?}, e1 {:?}, e2 {:?}",
                model.plane.normal.as_slice(),
                model.plane.e1.as_slice(),
                model.plane.e2.as_slice()
            );
            for b in &model.bodies {
                println!(
                    "body {} parent {:?} mass {:.6} inertia {:.6} com {:?} joints {:?}",
                    b.name,
                    b.parent,
                    b.mass,
                    b.inertia,
                    b.com.as_slice(),
                    b.joints
                );
            }
            for j in &model.joints {
                println!(
                    "joint {} qpos {} sign {} {:?} anchor {:?} range {:?}",
                    j.name,
                    j.qpos,
                    j.sign,
                    j.kind,
                    j.anchor.as_slice(),
                    j.range
                );
            }
            for g in &model.geoms {
                println!("geom {:?} body {:?} {:?}", g.name, g.body, g.shape);
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
