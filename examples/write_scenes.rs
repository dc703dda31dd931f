//! Writes the scene files of the validation reports (`dhpd::validation::scenes`)
//! so that every case a report talks about runs with `dhpd run FILE`.
//!
//! ```text
//! cargo run --release --example write_scenes
//! ```

fn main() -> std::io::Result<()> {
    for file in dhpd::validation::scenes::catalogue() {
        let path = std::path::Path::new(&file.path);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        std::fs::write(path, &file.text)?;
        println!("{}", file.path);
    }
    Ok(())
}
