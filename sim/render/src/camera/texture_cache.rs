//! A disk cache of the generated ground textures' texels, so that a run, its render worker
//! and every later run of the same program with the same seed skip generating them (about
//! 20 ms of each process's set-up, each on its own core).
//!
//! An entry is valid only for the program that wrote it (the key holds the executable's
//! path, size and modification time) and its seed, and it carries a checksum of everything
//! in it: anything else (no cache folder, a missing, short, damaged or foreign file, a
//! folder that cannot be written) and the texels are generated, exactly as they would have
//! been. The cache changes how long a set-up takes, never a texel: a test compares what
//! comes back with what [`GroundTextures::generate`] gives.
//!
//! The folder is `$CARFOLLOW_CACHE_DIR/ground-textures` (an empty `CARFOLLOW_CACHE_DIR`
//! turns the cache off), else `$XDG_CACHE_HOME/carfollow/ground-textures`, else
//! `$HOME/.cache/carfollow/ground-textures`. It keeps the newest [`KEEP`] entries, about
//! 1 MB each.

use super::textures::{GroundTextures, LAYERS, LEVEL_COUNT, TEXTURE_SIZE};
use std::path::{Path, PathBuf};
use vehicle::fnv1a64;

/// The environment variable that names the cache's parent folder (empty: no cache).
pub const CACHE_DIR_ENV: &str = "CARFOLLOW_CACHE_DIR";

/// How many entries the folder keeps: the oldest beyond that are removed after a write.
pub const KEEP: usize = 32;

/// What a cache file starts with: its format.
const MAGIC: &[u8; 8] = b"CFGTEX01";

/// Every mip level's 8-bit texels, layer after layer ([`GroundTextures::texels`]), for
/// the scene seed `seed`: from the cache when it holds them for this program, else
/// generated (and cached, when the folder can be written).
pub fn ground_texels(seed: u64) -> Vec<Vec<u8>> {
    match (cache_dir(), program_key()) {
        (Some(dir), Some(key)) => texels_cached_in(&dir, key, seed),
        _ => generated_texels(seed),
    }
}

/// [`ground_texels`] with the cache in `dir` and the program's key `key`.
pub fn texels_cached_in(dir: &Path, key: u64, seed: u64) -> Vec<Vec<u8>> {
    let path = dir.join(format!("{seed:016x}-{key:016x}.bin"));
    if let Some(levels) = std::fs::read(&path).ok().and_then(|b| parse(&b, key, seed)) {
        return levels;
    }
    let levels = generated_texels(seed);
    // A cache that cannot be written is no cache: the run goes on without it.
    let _ = store(dir, &path, &encode(&levels, key, seed));
    levels
}

/// The texels, generated.
fn generated_texels(seed: u64) -> Vec<Vec<u8>> {
    let textures = GroundTextures::generate(seed);
    (0..textures.level_count() as usize)
        .map(|level| textures.texels(level))
        .collect()
}

/// The cache folder, from the environment.
fn cache_dir() -> Option<PathBuf> {
    let base = match std::env::var_os(CACHE_DIR_ENV) {
        Some(dir) if dir.is_empty() => return None,
        Some(dir) => PathBuf::from(dir),
        None => match std::env::var_os("XDG_CACHE_HOME").filter(|d| !d.is_empty()) {
            Some(dir) => PathBuf::from(dir).join("carfollow"),
            None => PathBuf::from(std::env::var_os("HOME").filter(|d| !d.is_empty())?)
                .join(".cache")
                .join("carfollow"),
        },
    };
    Some(base.join("ground-textures"))
}

/// This program's identity: its path, size and modification time, hashed. Another build
/// (whose generator may differ) has another key.
fn program_key() -> Option<u64> {
    let exe = std::env::current_exe().ok()?;
    let meta = std::fs::metadata(&exe).ok()?;
    let modified = meta
        .modified()
        .ok()?
        .duration_since(std::time::UNIX_EPOCH)
        .ok()?;
    let mut bytes = exe.as_os_str().as_encoded_bytes().to_vec();
    bytes.extend(meta.len().to_le_bytes());
    bytes.extend(modified.as_nanos().to_le_bytes());
    Some(fnv1a64(&bytes))
}

/// How many texels level `level` holds, over every layer.
fn level_len(level: usize) -> usize {
    LAYERS * (TEXTURE_SIZE >> level).pow(2)
}

/// A cache file: the magic, the key, the seed, every level's texels, then the FNV-1a hash
/// of all that.
fn encode(levels: &[Vec<u8>], key: u64, seed: u64) -> Vec<u8> {
    let mut out = Vec::with_capacity(24 + levels.iter().map(Vec::len).sum::<usize>() + 8);
    out.extend_from_slice(MAGIC);
    out.extend(key.to_le_bytes());
    out.extend(seed.to_le_bytes());
    for level in levels {
        out.extend_from_slice(level);
    }
    let hash = fnv1a64(&out);
    out.extend(hash.to_le_bytes());
    out
}

/// The levels a cache file holds, if it is whole and was written for `key` and `seed`.
fn parse(bytes: &[u8], key: u64, seed: u64) -> Option<Vec<Vec<u8>>> {
    let lens: Vec<usize> = (0..LEVEL_COUNT).map(level_len).collect();
    let body_len = 24 + lens.iter().sum::<usize>();
    if bytes.len() != body_len + 8 {
        return None;
    }
    let (body, hash) = bytes.split_at(body_len);
    if &body[..8] != MAGIC
        || body[8..16] != key.to_le_bytes()
        || body[16..24] != seed.to_le_bytes()
        || hash != fnv1a64(body).to_le_bytes()
    {
        return None;
    }
    let mut rest = &body[24..];
    Some(
        lens.iter()
            .map(|&len| {
                let (level, tail) = rest.split_at(len);
                rest = tail;
                level.to_vec()
            })
            .collect(),
    )
}

/// Writes `bytes` to `path` whole or not at all (a file of its own, then renamed over), so
/// that runs started side by side never read half a file; then removes the oldest entries
/// beyond [`KEEP`].
fn store(dir: &Path, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    // Unique to this process and call: threads of one process may write at once.
    static WRITES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let write = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let partial = path.with_extension(format!("{}-{write}.part", std::process::id()));
    std::fs::write(&partial, bytes)?;
    if let Err(e) = std::fs::rename(&partial, path) {
        let _ = std::fs::remove_file(&partial);
        return Err(e);
    }
    let mut entries: Vec<(std::time::SystemTime, PathBuf)> = std::fs::read_dir(dir)?
        .filter_map(Result::ok)
        .filter(|e| e.path().extension().is_some_and(|x| x == "bin"))
        .filter_map(|e| Some((e.metadata().ok()?.modified().ok()?, e.path())))
        .collect();
    if entries.len() > KEEP {
        // Newest first; ties broken by name, so that every process agrees.
        entries.sort_by(|a, b| b.cmp(a));
        for (_, old) in &entries[KEEP..] {
            let _ = std::fs::remove_file(old);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "carfollow-texture-cache-{name}-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn the_cache_gives_the_generated_texels_written_or_read() {
        let dir = temp_dir("roundtrip");
        let generated = generated_texels(5);
        assert_eq!(generated.len(), LEVEL_COUNT);
        // Written on the first call, read on the second: the same texels both times.
        assert_eq!(texels_cached_in(&dir, 11, 5), generated);
        let files: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(files.len(), 1, "one entry and no partial file");
        assert_eq!(texels_cached_in(&dir, 11, 5), generated);
        // Another seed is another entry.
        assert_eq!(texels_cached_in(&dir, 11, 6), generated_texels(6));
        assert_ne!(generated_texels(6), generated);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_damaged_or_foreign_entry_is_generated_again() {
        let dir = temp_dir("damaged");
        let generated = generated_texels(2);
        texels_cached_in(&dir, 7, 2);
        let path = dir.join(format!("{:016x}-{:016x}.bin", 2, 7));
        let good = std::fs::read(&path).unwrap();
        assert!(parse(&good, 7, 2).is_some());
        // Another program's key or seed, a flipped texel, a short file: not taken.
        assert!(parse(&good, 8, 2).is_none());
        assert!(parse(&good, 7, 3).is_none());
        let mut flipped = good.clone();
        flipped[1000] ^= 1;
        assert!(parse(&flipped, 7, 2).is_none());
        assert!(parse(&good[..good.len() - 1], 7, 2).is_none());
        // A damaged file on disk: the texels are generated, and the entry mended.
        std::fs::write(&path, &flipped).unwrap();
        assert_eq!(texels_cached_in(&dir, 7, 2), generated);
        assert_eq!(std::fs::read(&path).unwrap(), good);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_that_cannot_be_written_only_costs_the_generation() {
        let dir = temp_dir("unwritable");
        // A file where the folder should be.
        std::fs::write(&dir, b"not a folder").unwrap();
        assert_eq!(texels_cached_in(&dir, 1, 4), generated_texels(4));
        std::fs::remove_file(&dir).unwrap();
    }

    #[test]
    fn the_folder_keeps_the_newest_entries() {
        let dir = temp_dir("keep");
        std::fs::create_dir_all(&dir).unwrap();
        // Stand-ins for old entries, oldest first.
        let t0 = std::time::SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(1_000_000);
        for k in 0..KEEP + 3 {
            let p = dir.join(format!("old{k:03}.bin"));
            std::fs::write(&p, b"x").unwrap();
            let f = std::fs::File::options().write(true).open(&p).unwrap();
            f.set_modified(t0 + std::time::Duration::from_secs(k as u64))
                .unwrap();
        }
        texels_cached_in(&dir, 3, 1);
        let mut left: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left.len(), KEEP);
        // The new entry stays; the four oldest stand-ins went.
        assert!(left.contains(&format!("{:016x}-{:016x}.bin", 1, 3)));
        let stand_ins: Vec<&String> = left.iter().filter(|n| n.starts_with("old")).collect();
        assert_eq!(stand_ins.len(), KEEP - 1);
        assert!(stand_ins.iter().all(|n| n.as_str() > "old003.bin"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
