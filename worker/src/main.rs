//! `moorfret-worker` binary.

fn main() {
    eprintln!("moorfret-worker: the job loop is not available yet in this version");
    std::process::exit(2);
}
