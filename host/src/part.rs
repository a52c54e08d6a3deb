//! Part files: what `smlt render --shard K/N` writes and `smlt merge` combines.
//!
//! A part is an OpenEXR file. Its `R`, `G`, `B` channels hold the part's own normalised image
//! (to look at); the exact f64 splat sums S are stored bit for bit as two `u32` channels per
//! colour (`S.R.hi`, `S.R.lo`, …); a layer attribute `smltPart` holds, as JSON, everything else
//! a merge needs: the render's identity (scene and its hash, view, the render's [`Settings`]
//! serialised whole, the smlt version and the kernels module's hash), the shard index, W, the acceptance and
//! NaN/Inf tallies, the candidates traced, and the moments of the bootstrap's and the large
//! steps' targets (f64 values as their bit patterns, so nothing is rounded on the way), and a
//! checksum over the header and the sums: a part changed after it was written (a digit of its
//! JSON edited, a bit of a sum flipped) is refused by name. Merging adds the accumulations in
//! shard order and normalises once: the image the unsplit render gives, up to f64 rounding.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use shared::normalisation::Moments;

use crate::render::{Accumulation, Integrator, Rendered, Settings, Shard, Stats};

/// The `format` value of a part written by this version.
pub const FORMAT: &str = "smlt-part-5";
/// The layer attribute holding the part's JSON.
const ATTRIBUTE: &str = "smltPart";

/// What makes two parts parts of the same render: the scene, the view, the render's settings
/// as they are (serialised whole, so a setting added to [`Settings`] is compared with no
/// further edit), and the versions that rendered it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Identity {
    /// The scene's `SceneData::name`: its file path, or a built-in scene's name.
    pub scene: String,
    /// A hash of the scene's files (the glTF and its buffers).
    pub scene_hash: String,
    /// The view: 1-based index among the scene file's cameras.
    pub view: u32,
    /// The render's settings, with the shard index of the first part (every part's own
    /// index is its header's `shard`).
    pub settings: Settings,
    /// The smlt version that rendered it.
    pub smlt_version: String,
    /// The content hash of the kernels module it ran (`crate::hash`).
    pub kernels: String,
    /// Whether `--method auto` chose the method, by a pilot on this shard's machine (each
    /// shard runs its own, so shards can choose differently; a merge then says which to render
    /// again).
    #[serde(default)]
    pub chosen_by_auto: bool,
}

impl Identity {
    /// The identity of a render of `scene` (name, hash, view) with `s`.
    pub fn new(scene: &str, scene_hash: &str, view: u32, s: &Settings) -> Self {
        Identity {
            scene: scene.to_string(),
            scene_hash: scene_hash.to_string(),
            view,
            settings: Settings { shard: Shard { index: 1, ..s.shard }, ..s.clone() },
            smlt_version: env!("CARGO_PKG_VERSION").to_string(),
            kernels: crate::hash::content_hash(crate::gpu::KERNELS_SPV),
            chosen_by_auto: false,
        }
    }

    /// The identity as that of a render whose method `--method auto` chose.
    pub fn chosen_by_auto(self) -> Self {
        Identity { chosen_by_auto: true, ..self }
    }

    /// Whether a render could have this identity: its method is one the command line names (a
    /// tree of depth 0 or 9, a reject chain of length 1, … are none), and it has pixels.
    pub fn check(&self) -> Result<(), String> {
        let method = self.settings.method();
        if method.to_string().parse::<crate::render::Method>() != Ok(method) {
            return Err(format!("its method {method:?} is none that smlt renders"));
        }
        if self.settings.width == 0 || self.settings.height == 0 || self.settings.candidates == 0 {
            return Err("it has no pixels or no candidates".to_string());
        }
        Ok(())
    }

    /// The first value in which `self` and `other` differ, as "where a vs b" (where is the
    /// field's path in words, e.g. `integrator Metropolis chains mutation p large 0.3 vs 0.5`
    /// for a setting), walking every field of both.
    pub fn difference(&self, other: &Identity) -> Option<String> {
        // How the method was chosen is no difference: a shard rendered again with the method
        // auto chose elsewhere belongs with the others. Where auto chose on a shard and the
        // methods differ, everything but the integrator is compared first, so that the merge
        // names what rendering again with one method would not mend.
        let value = |id: &Identity, integrator: Option<Integrator>| {
            let mut id = Identity { chosen_by_auto: false, ..id.clone() };
            if let Some(integrator) = integrator {
                id.settings.integrator = integrator;
            }
            serde_json::to_value(id)
        };
        let compare =
            |integrator: Option<Integrator>| match (value(self, integrator), value(other, integrator)) {
                (Ok(a), Ok(b)) => first_difference("", &a, &b),
                _ => Some("their identities cannot be compared".to_string()),
            };
        let (a, b) = (self.settings.method(), other.settings.method());
        if a == b {
            return compare(None);
        }
        if !(self.chosen_by_auto || other.chosen_by_auto) {
            return Some(format!("method {a} vs {b}"));
        }
        compare(Some(Integrator::PathTracer)).or_else(|| {
            Some(format!(
                "method {a} vs {b}, chosen by --method auto on a shard: render the shards again with \
                 --method {a} or --method {b}, the same on all"
            ))
        })
    }
}

/// The first place in which two JSON values differ, as "where a vs b": the object keys on the
/// way, in words (the settings' own key left out).
fn first_difference(path: &str, a: &serde_json::Value, b: &serde_json::Value) -> Option<String> {
    use serde_json::Value;
    let at = |key: &str| match (path, key) {
        ("", "settings") => String::new(),
        ("", _) => key.replace('_', " "),
        _ => format!("{path} {}", key.replace('_', " ")),
    };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys = x.keys().chain(y.keys().filter(|k| !x.contains_key(*k)));
            for key in keys {
                let (u, v) = (x.get(key).unwrap_or(&Value::Null), y.get(key).unwrap_or(&Value::Null));
                if let Some(d) = first_difference(&at(key), u, v) {
                    return Some(d);
                }
            }
            None
        }
        _ if a == b => None,
        _ => Some(format!("{path} {a} vs {b}")),
    }
}

/// f64 values as their bits (hex), so that JSON keeps them exactly.
mod bits {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&format!("{:016x}", v.to_bits()))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        let s = String::deserialize(d)?;
        u64::from_str_radix(&s, 16).map(f64::from_bits).map_err(serde::de::Error::custom)
    }
}

/// Moments as exact JSON.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
struct ExactMoments {
    count: u64,
    #[serde(with = "bits")]
    sum: f64,
    #[serde(with = "bits")]
    sum_sq: f64,
}

impl From<Moments> for ExactMoments {
    fn from(m: Moments) -> Self {
        ExactMoments { count: m.count, sum: m.sum, sum_sq: m.sum_sq }
    }
}

impl From<ExactMoments> for Moments {
    fn from(m: ExactMoments) -> Self {
        Moments { count: m.count, sum: m.sum, sum_sq: m.sum_sq }
    }
}

/// The JSON header of a part.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Header {
    format: String,
    identity: Identity,
    shard: u32,
    iterations: u64,
    render_seconds: f64,
    device: String,
    #[serde(with = "bits")]
    weight: f64,
    #[serde(with = "bits")]
    accepted: f64,
    invalid: u64,
    candidates: u64,
    large_steps: ExactMoments,
    bootstrap: ExactMoments,
    /// FNV-1a of this header (with the checksum empty) and of the sums' bits: a part that was
    /// changed after it was written is refused.
    checksum: String,
}

/// The checksum of a header's JSON as written with an empty checksum, and of `sums`: over the
/// text itself, since JSON numbers need not read back to the same bits.
fn checksum(json_with_empty_checksum: &str, sums: &[f64]) -> String {
    let mut bytes = json_with_empty_checksum.as_bytes().to_vec();
    bytes.extend(sums.iter().flat_map(|s| s.to_bits().to_le_bytes()));
    crate::hash::content_hash(&bytes)
}

/// The header member that holds the checksum, as serde_json writes it.
fn checksum_member(value: &str) -> String {
    format!("\"checksum\":\"{value}\"")
}

/// A part read back.
#[derive(Clone, Debug)]
pub struct Part {
    /// Where it was read from.
    pub path: PathBuf,
    /// The render it belongs to.
    pub identity: Identity,
    /// Its shard index (1-based).
    pub shard: u32,
    /// Iterations it ran.
    pub iterations: u64,
    /// Seconds of its iterations (a merge reports the largest part's).
    pub render_seconds: f64,
    /// The device it ran on.
    pub device: String,
    /// Its splat sums and tallies, which [`merge`] adds in shard order.
    pub accumulation: Accumulation,
    /// The bootstrap's moments (the same in every part of a render).
    pub bootstrap: Moments,
}

/// Why a part could not be written, read or merged (one line each).
#[derive(Debug, thiserror::Error)]
pub enum PartError {
    /// The file cannot be read as EXR.
    #[error("cannot read {0}: {1}")]
    Read(String, String),
    /// An EXR without a part header.
    #[error(
        "{0} is not an smlt part file (no {ATTRIBUTE} header; write parts with smlt render --shard K/N)"
    )]
    NotAPart(String),
    /// A malformed header or channels.
    #[error("{0} is a damaged part file: {1}")]
    Damaged(String, String),
    /// The file cannot be written.
    #[error("cannot write {0}: {1}")]
    Write(String, String),
    /// Merge needs at least one part.
    #[error("no part files given")]
    Empty,
    /// Two parts of different renders.
    #[error("{a} and {b} are parts of different renders ({difference})")]
    Mismatch {
        /// Path of one part.
        a: String,
        /// Path of the other part.
        b: String,
        /// The first difference.
        difference: String,
    },
    /// The same shard twice.
    #[error("shard {shard} is given twice: {a} and {b}")]
    Duplicate {
        /// The shard, K/N.
        shard: String,
        /// Path of one part giving the shard.
        a: String,
        /// Path of the other.
        b: String,
    },
    /// A shard is missing.
    #[error("shard {0} is missing: a merge needs every shard 1..{1} of the render")]
    Missing(String, u32),
}

/// Writes `r` (a shard's render) as a part file at `path` (to a temporary file renamed into
/// place).
pub fn write_part(
    path: &Path,
    identity: &Identity,
    shard: Shard,
    r: &Rendered,
    device: &str,
) -> Result<(), PartError> {
    use exr::prelude::*;
    let fail = |e: &dyn std::fmt::Display| PartError::Write(path.display().to_string(), e.to_string());
    let header = Header {
        format: FORMAT.to_string(),
        identity: identity.clone(),
        shard: shard.index,
        iterations: r.stats.iterations,
        render_seconds: r.stats.render_seconds,
        device: device.to_string(),
        weight: r.accumulation.weight,
        accepted: r.accumulation.accepted,
        invalid: r.accumulation.invalid,
        candidates: r.accumulation.candidates,
        large_steps: r.accumulation.large_steps.into(),
        bootstrap: r.bootstrap.into(),
        checksum: String::new(),
    };
    let blank = serde_json::to_string(&header).map_err(|e| fail(&e))?;
    let sum = checksum(&blank, &r.accumulation.image);
    let json = blank.replacen(&checksum_member(""), &checksum_member(&sum), 1);
    let pixels = (r.width * r.height) as usize;
    let mut channels: Vec<AnyChannel<FlatSamples>> = Vec::new();
    for (i, name) in ["R", "G", "B"].iter().enumerate() {
        channels
            .push(AnyChannel::new(*name, FlatSamples::F32((0..pixels).map(|p| r.rgb[p * 3 + i]).collect())));
        let sums: Vec<u64> = (0..pixels).map(|p| r.accumulation.image[p * 3 + i].to_bits()).collect();
        channels.push(AnyChannel::new(
            format!("S.{name}.hi").as_str(),
            FlatSamples::U32(sums.iter().map(|b| (b >> 32) as u32).collect()),
        ));
        channels.push(AnyChannel::new(
            format!("S.{name}.lo").as_str(),
            FlatSamples::U32(sums.iter().map(|b| *b as u32).collect()),
        ));
    }
    let mut attributes = LayerAttributes::named("part");
    let text = Text::new_or_none(&json).ok_or_else(|| fail(&"the part header is not EXR text"))?;
    attributes.other.insert(Text::from(ATTRIBUTE), AttributeValue::Text(text));
    let layer = Layer::new(
        (r.width as usize, r.height as usize),
        attributes,
        crate::output::EXR_ENCODING,
        AnyChannels::sort(channels.into()),
    );
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    Image::from_layer(layer).write().to_file(&tmp).map_err(|e| fail(&e))?;
    std::fs::rename(&tmp, path).map_err(|e| fail(&e))
}

/// Reads a part file.
pub fn read_part(path: &Path) -> Result<Part, PartError> {
    use exr::prelude::*;
    let shown = path.display().to_string();
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(path)
        .map_err(|e| PartError::Read(shown.clone(), e.to_string()))?;
    let damaged = |why: &str| PartError::Damaged(shown.clone(), why.to_string());
    let layer = image.layer_data.first().ok_or_else(|| PartError::NotAPart(shown.clone()))?;
    let Some(AttributeValue::Text(text)) = layer.attributes.other.get(&Text::from(ATTRIBUTE)) else {
        return Err(PartError::NotAPart(shown));
    };
    // The format first, so that a part of another format is named as such, not as damaged.
    let value: serde_json::Value =
        serde_json::from_str(&text.to_string()).map_err(|e| damaged(&e.to_string()))?;
    let format = value.get("format").and_then(|f| f.as_str()).unwrap_or("none");
    if format != FORMAT {
        return Err(damaged(&format!("format {format} (this smlt reads {FORMAT})")));
    }
    let header: Header = serde_json::from_value(value).map_err(|e| damaged(&e.to_string()))?;
    header.identity.check().map_err(|e| damaged(&e))?;
    let id = &header.identity;
    let (width, height) = (id.settings.width as usize, id.settings.height as usize);
    let pixels = width * height;
    if layer.size.width() != width || layer.size.height() != height {
        return Err(damaged("its image size is not the header's"));
    }
    let by_name: HashMap<String, &FlatSamples> =
        layer.channel_data.list.iter().map(|c| (c.name.to_string(), &c.sample_data)).collect();
    let words = |name: &str| -> std::result::Result<&Vec<u32>, PartError> {
        match by_name.get(name) {
            Some(FlatSamples::U32(v)) if v.len() == pixels => Ok(v),
            _ => Err(damaged(&format!("no u32 channel {name}"))),
        }
    };
    let mut sums = vec![0.0f64; pixels * 3];
    for (i, name) in ["R", "G", "B"].iter().enumerate() {
        let (hi, lo) = (words(&format!("S.{name}.hi"))?, words(&format!("S.{name}.lo"))?);
        for p in 0..pixels {
            sums[p * 3 + i] = f64::from_bits(((hi[p] as u64) << 32) | lo[p] as u64);
        }
    }
    let blank = text.to_string().replacen(&checksum_member(&header.checksum), &checksum_member(""), 1);
    if header.checksum.is_empty() || checksum(&blank, &sums) != header.checksum {
        return Err(damaged(
            "its checksum does not match its header and sums: it was changed after it was written",
        ));
    }
    if header.shard == 0 || header.shard > id.settings.shard.count {
        return Err(damaged(&format!("shard {} of {}", header.shard, id.settings.shard.count)));
    }
    Ok(Part {
        path: path.to_path_buf(),
        identity: header.identity,
        shard: header.shard,
        iterations: header.iterations,
        render_seconds: header.render_seconds,
        device: header.device,
        accumulation: Accumulation {
            image: sums,
            weight: header.weight,
            accepted: header.accepted,
            invalid: header.invalid,
            candidates: header.candidates,
            large_steps: header.large_steps.into(),
        },
        bootstrap: header.bootstrap.into(),
    })
}

/// Merges the parts of one render into its image: checks that they are every shard of the
/// same render exactly once, adds their accumulations in shard order and normalises once.
pub fn merge(parts: &[Part]) -> Result<Rendered, PartError> {
    let first = parts.first().ok_or(PartError::Empty)?;
    let show = |p: &Part| p.path.display().to_string();
    for p in &parts[1..] {
        if let Some(difference) = first.identity.difference(&p.identity) {
            return Err(PartError::Mismatch { a: show(first), b: show(p), difference });
        }
        if p.bootstrap != first.bootstrap {
            return Err(PartError::Mismatch {
                a: show(first),
                b: show(p),
                difference: "their bootstraps differ: were they rendered by different smlt versions?".into(),
            });
        }
    }
    let count = first.identity.settings.shard.count;
    let mut by_shard: Vec<Option<&Part>> = vec![None; count as usize];
    for p in parts {
        let slot = &mut by_shard[(p.shard - 1) as usize];
        if let Some(other) = slot {
            return Err(PartError::Duplicate {
                shard: format!("{}/{count}", p.shard),
                a: show(other),
                b: show(p),
            });
        }
        *slot = Some(p);
    }
    if let Some(k) = by_shard.iter().position(Option::is_none) {
        return Err(PartError::Missing(format!("{}/{count}", k + 1), count));
    }
    let settings = &first.identity.settings;
    let mut acc = Accumulation::new(settings.width as usize * settings.height as usize);
    let mut stats = Stats { chains: settings.chains(), ..Default::default() };
    for p in by_shard.into_iter().flatten() {
        acc.merge(&p.accumulation);
        stats.iterations = stats.iterations.max(p.iterations);
        stats.render_seconds = stats.render_seconds.max(p.render_seconds);
    }
    Ok(Rendered::from_accumulation(settings, first.bootstrap, acc, stats))
}

#[cfg(test)]
mod tests {
    use serde_json::Value;

    use super::*;
    use crate::render::{Method, Schedule};

    fn identity() -> Identity {
        let s = Settings::default().with_method("path-s3".parse::<Method>().unwrap());
        Identity::new("scene", "hash", 1, &Settings { shard: Shard { index: 2, count: 3 }, ..s })
    }

    /// Every leaf of `v` (a number, string or bool inside objects and arrays), with its path.
    fn leaves(v: &Value, path: Vec<String>, out: &mut Vec<Vec<String>>) {
        match v {
            Value::Object(o) => {
                o.iter().for_each(|(k, x)| leaves(x, [path.clone(), vec![k.clone()]].concat(), out))
            }
            _ => out.push(path),
        }
    }

    /// Changing any one value of the identity — every field of the settings included, found by
    /// walking their serialisation, so a setting added later is covered with no edit here —
    /// makes `first_difference` name it, and the same identity has none (`difference` leaves
    /// out only `chosen_by_auto`: `identities_of_no_render_are_refused`).
    #[test]
    fn every_value_of_the_identity_tells_renders_apart() {
        let id = identity();
        assert_eq!(id.difference(&id.clone()), None);
        assert_eq!(id.settings.shard.index, 1, "the identity holds no part's own shard index");
        let value = serde_json::to_value(&id).unwrap();
        let mut paths = Vec::new();
        leaves(&value, Vec::new(), &mut paths);
        assert!(paths.len() > 15, "{} leaves", paths.len());
        for path in paths {
            let mut changed = value.clone();
            let leaf = path.iter().fold(&mut changed, |v, k| &mut v[k.as_str()]);
            *leaf = match leaf.take() {
                Value::Number(n) => Value::from(n.as_f64().unwrap() + 1.0),
                Value::String(s) => Value::from(format!("{s}x")),
                Value::Bool(b) => Value::from(!b),
                other => panic!("{path:?}: {other}"),
            };
            let difference = first_difference("", &value, &changed).unwrap_or_default();
            let last = path.last().unwrap().replace('_', " ");
            assert!(difference.contains(&last), "{path:?}: {difference}");
        }
    }

    /// A part's identity names a render smlt could have made, or the part is refused.
    #[test]
    fn identities_of_no_render_are_refused() {
        assert_eq!(identity().check(), Ok(()));
        for schedule in
            [Schedule::Tree(0), Schedule::Tree(9), Schedule::RejectChain(1), Schedule::RejectChain(65)]
        {
            let mut id = identity();
            id.settings.metropolis_mut().unwrap().schedule = schedule;
            assert!(id.check().unwrap_err().contains("is none that smlt renders"), "{schedule:?}");
        }
        let mut id = identity();
        id.settings.width = 0;
        assert!(id.check().is_err());
        // Another method is named as such (before anything else: this one's width is 0 too).
        let other = Identity { settings: id.settings.clone().with_method(Method::PathTracer), ..identity() };
        assert_eq!(identity().difference(&other).as_deref(), Some("method path-s3 vs pt"));
        // Where auto chose on a shard, the merge says what to render again...
        let pt = Identity { settings: identity().settings.with_method(Method::PathTracer), ..identity() };
        let said = identity().chosen_by_auto().difference(&pt.clone().chosen_by_auto()).unwrap();
        assert!(said.starts_with("method path-s3 vs pt, chosen by --method auto on a shard"), "{said}");
        assert!(said.ends_with("with --method path-s3 or --method pt, the same on all"), "{said}");
        // ...after what another method would not mend.
        let mut seeded = pt.clone().chosen_by_auto();
        seeded.settings.seed += 1;
        let said = identity().chosen_by_auto().difference(&seeded).unwrap();
        assert!(said.contains("seed") && !said.contains("--method"), "{said}");
        let said = identity().chosen_by_auto().difference(&other).unwrap();
        assert!(said.contains("width") && !said.contains("--method"), "{said}");
        // The same choice on every shard merges, and so does a shard rendered again with the
        // method auto chose on the others.
        assert_eq!(identity().chosen_by_auto().difference(&identity().chosen_by_auto()), None);
        assert_eq!(identity().chosen_by_auto().difference(&identity()), None);
    }

    /// A field the settings gain (here added to a part's JSON, as a newer smlt would write it)
    /// is never dropped on the way: the part is refused as unreadable rather than merged with
    /// parts that lack it, and the comparison of two such identities names it.
    #[test]
    fn a_field_added_to_the_settings_refuses_the_merge() {
        let value = serde_json::to_value(identity()).unwrap();
        let mut added = value.clone();
        added["settings"]["integrator"]["Metropolis"]["chains"]["new_knob"] = Value::from(3);
        let e = serde_json::from_value::<Identity>(added.clone()).unwrap_err().to_string();
        assert!(e.contains("new_knob"), "{e}");
        let difference = first_difference("", &value, &added).unwrap();
        assert!(difference.contains("new knob null vs 3"), "{difference}");
        let mut top = value.clone();
        top["settings"]["new_knob"] = Value::from(true);
        assert!(serde_json::from_value::<Identity>(top).is_err());
    }
}
