//! `smlt scene`: writes one of the generated scenes (or a variant of a scene the user has) as
//! glTF.

use std::path::PathBuf;

/// `smlt scene`'s flags.
#[derive(clap::Args)]
pub struct Args {
    /// Scene name: cornell, atrium, nave, sunblind, slit, lamps, caustic, materials, textured,
    /// smooth, cutout, or sponza-banner (with --from).
    pub name: String,
    /// Output .gltf path.
    #[arg(long)]
    pub out: PathBuf,
    /// Split every quad n × n times (raises the triangle count; the image stays the same).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256))]
    pub tessellation: u32,
    /// The source a variant is written from (sponza-banner: the Dabrovic Sponza glTF).
    #[arg(long)]
    pub from: Option<PathBuf>,
}

/// Runs `smlt scene`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let text = match (a.name.as_str(), &a.from) {
        ("sponza-banner", Some(from)) => smlt::scenes::sponza_banner::sponza_banner(from, &a.out)?,
        ("sponza-banner", None) => anyhow::bail!(
            "sponza-banner is written from the Dabrovic Sponza: add --from PATH/sponza_dabrovic.gltf"
        ),
        (name, _) => match smlt::scenes::generate(name, a.tessellation) {
            Some(text) => text,
            None => anyhow::bail!(
                "unknown scene '{name}': known scenes are {} and sponza-banner",
                smlt::scenes::GENERATED.join(", ")
            ),
        },
    };
    std::fs::write(&a.out, text).map_err(|e| anyhow::anyhow!("cannot write {}: {e}", a.out.display()))?;
    println!("wrote {}", a.out.display());
    Ok(())
}
