//! Throughput benchmark: ufcsr counting against the decode-only ceiling, on
//! the same tiles in the same run, with the ratios the targets name
//! (counting stage ≥ 0.75 / 0.90 of decoding, whole process ≥ 0.60, peak
//! memory ≤ 512 MiB, docs/performance.md). Settled comparisons (the
//! original per-pixel hash map, the Adler-32 check's cost, reading tiles
//! against mapping them) are no longer run.
//!
//! `cargo bench --bench throughput -- [--frames N] [--block N] [--archive DIR]... [--also DIR]... [--keep DIR] [--projection] [--kernels | --processes]`
//!
//! For each archive (each `--archive`; without one, a generated archive and
//! then each `--also`) it prints the
//! issue's targets in one run: the counting stage of `analyze()` in Mpixel/s
//! against decoding the same tiles alone, with the per-part tables (the
//! default) and without (`--frames-csv off`), and the whole
//! `ufcsr-analyze` process against a whole process that only decodes the
//! tiles (this binary with `--decode-files`) and against itself with
//! `--texel-area off` (the per-texel angular area's cost, CPU and wall),
//! alternated.
//!
//! The ceiling is decoding with the png crate, as the issue defines it.
//! ufcsr reads tiles with its own decoder (one inflate that also checks the
//! zlib checksum, where the png crate path needed a second), so each figure
//! is also given against ufcsr's decoder alone (`--decode-files-ufcsr`):
//! that ratio is the cost of counting itself.
//!
//! `--keep DIR` writes the generated archive to DIR and leaves it there.
//! `--processes` times only the whole processes (5 alternated rounds).
//! `--projection` gives the generated archive's manifest the eyes'
//! projection and fps (`rig.settings`, 107° horizontal at 60 fps, as
//! `ufcsr-capture` writes them), so the default analysis also measures
//! per-texel angular area (the default heatmap's measure), as it does on a
//! capture.
//! `--kernels` times only the row kernels on decoded rows (one thread, each
//! kernel this CPU runs) and the AVX-512 kernel with the per-part tally, in
//! its own pass and as a separate pass, for work on the kernels, and the
//! exact-counter floor: the least work an exact once-per-image counter must
//! do on the same tiles, and the counting-stage ratio it leaves room for
//! (every run prints both, after the rest), and the angular-area floor (one
//! add per texel run into the per-texel sums) on those tiles and, cold and
//! in order, over the whole archive.
//!
//! Without `--archive` it generates a realistic archive (by default 24
//! frames, 1,200 tiles of 1284×1620,
//! 5×5 per eye, mostly empty; object tiles with smooth unique-colour
//! gradients and occlusion edges at 0.2–2 texels per pixel).

// Test and benchmark code may use std::fs directly; production code goes
// through the file layer (clippy.toml, docs/reliability.md).
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;
use ufcsr::synthetic::{ArchiveSpec, write_archive};
use ufcsr::{AnalyzeOptions, Classifier, Counts, Fcsp, analyze, scan_image};
use ufcsr::{AtomicColorSet, SeenSet, color_key};
use ufcsr::{EyeProjection, Legend, PartLookup, PartPixels, PartRows, Pidt, PixelLayout, TileView};
use ufcsr::{Kernel, RowScan};
use ufcsr::{RowReader, read_file};

struct Args {
    frames: u32,
    block: u32,
    archives: Vec<PathBuf>,
    /// Archives benched after the generated one.
    also: Vec<PathBuf>,
    /// Decode the tiles listed in this file and exit (the decode-only
    /// process): with the png crate (`--decode-files`, the ceiling) or with
    /// ufcsr's own tile decoder (`--decode-files-ufcsr`).
    decode_files: Option<(PathBuf, Decoder)>,
    keep: Option<PathBuf>,
    /// The generated archive gives the eyes' projection and fps.
    projection: bool,
    /// Only the row kernels on decoded rows (quick, for kernel work).
    kernels_only: bool,
    /// Only the whole processes (`--processes`: default against decode-only
    /// and against `--texel-area off`).
    processes_only: bool,
}

fn parse_args() -> Args {
    let mut args = Args {
        // 24 frames × 2 eyes × 25 tiles: the 1,200-tile archive issue 22 measured.
        frames: 24,
        block: 3,
        archives: Vec::new(),
        also: Vec::new(),
        decode_files: None,
        keep: None,
        projection: false,
        kernels_only: false,
        processes_only: false,
    };
    let mut iter = std::env::args().skip(1);
    while let Some(arg) = iter.next() {
        match arg.as_str() {
            "--frames" => args.frames = iter.next().and_then(|v| v.parse().ok()).unwrap_or(args.frames),
            "--block" => args.block = iter.next().and_then(|v| v.parse().ok()).unwrap_or(args.block),
            "--archive" => args.archives.extend(iter.next().map(PathBuf::from)),
            "--also" => args.also.extend(iter.next().map(PathBuf::from)),
            "--decode-files" => {
                args.decode_files = iter.next().map(|p| (PathBuf::from(p), Decoder::PngCrate))
            }
            "--decode-files-ufcsr" => {
                args.decode_files = iter.next().map(|p| (PathBuf::from(p), Decoder::Ufcsr))
            }
            "--keep" => args.keep = iter.next().map(PathBuf::from),
            "--kernels" => args.kernels_only = true,
            "--processes" => args.processes_only = true,
            "--projection" => args.projection = true,
            _ => {} // cargo bench passes --bench
        }
    }
    args
}

/// Peak resident memory of this process so far, in MiB (Linux).
fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("VmHWM:")).map(|l| l.to_string()))
        .and_then(|l| l.split_whitespace().nth(1).and_then(|kb| kb.parse::<f64>().ok()))
        .map(|kb| kb / 1024.0)
        .unwrap_or(f64::NAN)
}

/// Best of `runs` wall times, in seconds.
fn best_of<F: FnMut()>(runs: usize, mut work: F) -> f64 {
    (0..runs)
        .map(|_| {
            let start = Instant::now();
            work();
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Which decoder a decode-only run uses.
#[derive(Clone, Copy)]
enum Decoder {
    /// The png crate with its defaults: the ceiling.
    PngCrate,
    /// ufcsr's `RowReader` (one inflate, Adler-32 checked, chunk CRCs).
    Ufcsr,
}

impl Decoder {
    fn decode(self, files: &[PathBuf]) -> u64 {
        match self {
            Decoder::PngCrate => png_crate_decode(files),
            Decoder::Ufcsr => decode_only(files),
        }
    }
}

/// Decode only with ufcsr's reader: every row of every tile, nothing counted.
fn decode_only(files: &[PathBuf]) -> u64 {
    files
        .par_iter()
        .map(|path| {
            let bytes = read_file(path).unwrap();
            let mut reader = RowReader::new(path, &bytes).unwrap();
            let mut sum = 0u64;
            while let Some(row) = reader.next_row().unwrap() {
                sum += u64::from(black_box(row)[0]);
            }
            sum
        })
        .sum()
}

/// The png crate alone, with its defaults but the zlib Adler-32 check off
/// (the ceiling).
fn png_crate_decode(files: &[PathBuf]) -> u64 {
    files
        .par_iter()
        .map(|path| {
            let bytes = std::fs::read(path).unwrap();
            let mut options = png::DecodeOptions::default();
            options.set_ignore_adler32(true);
            let mut decoder = png::Decoder::new_with_options(std::io::Cursor::new(&bytes[..]), options);
            decoder.set_transformations(png::Transformations::EXPAND);
            let mut reader = decoder.read_info().unwrap();
            let mut sum = 0u64;
            while let Some(row) = reader.next_row().unwrap() {
                sum += u64::from(black_box(row.data())[0]);
            }
            reader.finish().unwrap();
            sum
        })
        .sum()
}

/// ufcsr's counting: decode + dense once-per-image counting, tiles read
/// whole as `analyze()` reads them.
fn ours(files: &[PathBuf], classifier: &Classifier) -> Counts {
    let counts = Counts::new();
    let strays = AtomicColorSet::new();
    let sets: Vec<Mutex<SeenSet>> =
        (0..rayon::current_num_threads()).map(|_| Mutex::new(SeenSet::new())).collect();
    files.par_iter().for_each(|path| {
        let mut seen = sets[rayon::current_thread_index().unwrap_or(0) % sets.len()].lock().unwrap();
        let bytes = read_file(path).unwrap();
        scan_image(path, &bytes, classifier, &mut seen, &strays).unwrap();
        counts.add_set(&mut seen);
    });
    counts
}

/// The row kernels alone, one thread, on rows decoded beforehand: nanoseconds
/// per pixel for each kernel this CPU runs, including the commit of each
/// tile's texels to the counts (with the selected kernel's count updates);
/// then the floor of any exact counter on the same tiles.
fn kernels_alone(files: &[PathBuf], classifier: &Classifier, lookup: Option<&PartLookup>) {
    let sample = sampled_tiles(files);
    let tiles = decoded_tiles(&sample);
    let pixels: usize = tiles
        .iter()
        .map(|(layout, rows)| rows.iter().map(|r| r.len() / layout.bytes_per_pixel()).sum::<usize>())
        .sum();
    let counts = Counts::new();
    let strays = AtomicColorSet::new();
    let mut seen = SeenSet::new();
    for kernel in [Kernel::Portable, Kernel::Avx2, Kernel::Avx512] {
        if kernel > Kernel::supported() {
            continue;
        }
        let mut by_class = [0u64; 3];
        let mut commit = 0.0;
        let scan = best_of(3, || {
            commit = 0.0;
            for (layout, rows) in &tiles {
                let kernel = RowScan::new(kernel, *layout, classifier);
                for row in rows {
                    kernel.scan(row, classifier, &mut seen, &strays, &mut by_class);
                }
                let start = Instant::now();
                counts.add_set(&mut seen);
                commit += start.elapsed().as_secs_f64();
            }
        });
        println!(
            "  {:<8} kernel alone (1 thread, decoded rows)  {:5.2} ns/pixel, of which commit {:4.2} ({} count updates)",
            kernel.name(),
            scan * 1e9 / pixels as f64,
            commit * 1e9 / pixels as f64,
            Kernel::selected().name()
        );
        black_box(by_class);
    }
    black_box(counts);
    if let Some(lookup) = lookup {
        parts_alone(&tiles, pixels, classifier, lookup);
    }
    exact_counter_floor(&sample, &tiles, pixels);
    angular_area_floor_whole(files);
}

/// The least an exact once-per-image counter must do, on the same decoded
/// tiles (one thread): set one bit in a per-image set for each texel pixel
/// whose colour differs from its left neighbour's, then add one to the count
/// of each distinct texel. Nothing else: no classification (the keys are
/// extracted beforehand, outside the timing), no per-part tally, no frame
/// dedupe, no colour checks. Two such counters: the crate's set and commit
/// (`SeenSet::insert`, `Counts::add_set`), and a plain bit set whose counts
/// are added by walking the same keys again; the floor is the cheaper. A
/// counting stage decodes with ufcsr's decoder and then counts, so its ratio
/// to the png crate's decode-only speed is at most `png / (ufcsr + floor)`,
/// all three timed here on the same tiles. Two looser bounds follow: the
/// plain set's bits with the analyzer's commit (the cheaper half of each,
/// which no counter combines: the commit finds words by marks the plain
/// set does not keep), and the bits alone (a counter whose counts cost
/// nothing).
fn exact_counter_floor(sample: &[PathBuf], tiles: &[(PixelLayout, Vec<Vec<u8>>)], pixels: usize) {
    let keys: Vec<Vec<u32>> = tiles.iter().map(|(layout, rows)| fresh_texel_keys(*layout, rows)).collect();
    let inserted: usize = keys.iter().map(Vec::len).sum();
    let counts = Counts::new();
    let mut seen = SeenSet::new();
    let mut commit = 0.0;
    let set = best_of(3, || {
        commit = 0.0;
        for tile in &keys {
            for &key in tile {
                seen.insert(key);
            }
            let start = Instant::now();
            counts.add_set(&mut seen);
            commit += start.elapsed().as_secs_f64();
        }
    });
    black_box(counts);
    // A second exact counter: the bits set with a plain OR, no marks; then
    // the same keys again, each adding one to its count where its bit is
    // still set and clearing it (so a texel counts once per tile).
    let mut words = vec![0u64; 1 << 18];
    let mut by_key = vec![0u32; 1 << 24];
    let mut bits = 0.0;
    let plain = best_of(3, || {
        bits = 0.0;
        for tile in &keys {
            let start = Instant::now();
            for &key in tile {
                words[(key >> 6) as usize] |= 1 << (key & 63);
            }
            bits += start.elapsed().as_secs_f64();
            for &key in tile {
                let word = &mut words[(key >> 6) as usize];
                let bit = 1u64 << (key & 63);
                by_key[key as usize] += u32::from(*word & bit != 0);
                *word &= !bit;
            }
        }
    });
    black_box(&by_key);
    angular_area_floor(&keys, pixels);
    let [png, own] = [Decoder::PngCrate, Decoder::Ufcsr].map(|decoder| {
        best_of(3, || {
            black_box(decoder.decode(sample));
        })
    });
    let [set, commit, plain, bits, png, own] =
        [set, commit, plain, bits, png, own].map(|s| s * 1e9 / pixels as f64);
    let (floor, bits_and_commit) = (set.min(plain), bits + commit);
    println!(
        "  exact-counter floor (1 thread): {:.1} % of the pixels are texels unlike their left neighbour; \
         set inserts + commit {set:.2} ns/pixel (commit {commit:.2}), or bits + counts by the same keys \
         {plain:.2} (bits {bits:.2}); decoding the same tiles {png:.2} (png crate), {own:.2} (ufcsr)",
        inserted as f64 * 100.0 / pixels as f64,
    );
    println!(
        "    the most a counting stage could reach (targets 0.75 default, 0.90 --frames-csv off): {:.2} \
         doing only the cheaper counter; {:.2} doing only the plain bits and the analyzer's commit (no \
         counter does both); {:.2} only setting the bits (nothing counted)",
        png / (own + floor),
        png / (own + bits_and_commit),
        png / (own + bits),
    );
}

/// The least an exact per-texel angular area must add, on the same keys
/// (one per texel pixel unlike its left neighbour: one per texel run, what
/// the counting kernels report) and one thread: each run's weight added to
/// its texel's sum in a dense table indexed by key, in the order the runs
/// come, and nothing else (no run found, no prefix sum read, no lock). Once
/// in `u64` sums (what the analyzer keeps: exact units of 2⁻⁴⁸ sr) and once
/// in `u32` (half the cache lines; it would need a carry to stay exact).
/// Against the CPU per pixel of an analysis with `--texel-area off` this is
/// the least the area can cost (docs/performance.md#per-texel-angular-area).
fn angular_area_floor(keys: &[Vec<u32>], pixels: usize) {
    let mut wide = vec![1u64; 1 << 24];
    let mut narrow = vec![1u32; 1 << 24];
    let weights = floor_weights();
    let per_pixel = |seconds: f64| seconds * 1e9 / pixels as f64;
    let u64_sums = best_of(3, || {
        for tile in keys {
            add_runs(&mut wide, tile, &weights);
        }
    });
    let u32_sums = best_of(3, || {
        for tile in keys {
            for (i, &key) in tile.iter().enumerate() {
                narrow[key as usize] = narrow[key as usize].wrapping_add(weights[i & 4095] as u32);
            }
        }
    });
    black_box((&wide, &narrow));
    println!(
        "  angular-area floor (1 thread): one add per texel run into the per-texel sums, {:.2} ns/pixel \
         (u64 sums), {:.2} (u32 sums)",
        per_pixel(u64_sums),
        per_pixel(u32_sums),
    );
}

/// The run weights the floors add (4,096 of them, cycled; above 2³² so that
/// a `u64` add is needed).
fn floor_weights() -> Vec<u64> {
    (0..4096u64).map(|i| 0x1_0000_0000 + i * 977).collect()
}

/// Each run's weight added to its texel's sum, in the runs' order.
#[inline]
fn add_runs(sums: &mut [u64], keys: &[u32], weights: &[u64]) {
    for (i, &key) in keys.iter().enumerate() {
        sums[key as usize] += weights[i & 4095];
    }
}

/// [`angular_area_floor`] over the whole archive rather than the 12 sampled
/// tiles, in the archive's order, once, into a fresh table: what the sums
/// cost when the texels a scenario shows do not stay in cache between tiles
/// (the sampled floor's best of three keeps its few tiles' lines cached, so
/// it is a lower bound; this is the cost of the dense table's adds on this
/// archive). At most 2²⁶ runs (256 MiB of keys) are kept; the pixels are
/// those of the tiles they came from.
fn angular_area_floor_whole(files: &[PathBuf]) {
    const MOST_RUNS: usize = 1 << 26;
    let (mut keys, mut pixels, mut tiles) = (Vec::new(), 0usize, 0usize);
    for chunk in files.chunks(8) {
        if keys.len() >= MOST_RUNS {
            break;
        }
        for (layout, rows) in decoded_tiles(chunk) {
            pixels += rows.iter().map(|r| r.len() / layout.bytes_per_pixel()).sum::<usize>();
            keys.extend(fresh_texel_keys(layout, &rows));
            tiles += 1;
        }
    }
    let mut sums = vec![1u64; 1 << 24];
    let weights = floor_weights();
    let start = Instant::now();
    add_runs(&mut sums, &keys, &weights);
    let seconds = start.elapsed().as_secs_f64();
    black_box(&sums);
    println!(
        "  angular-area floor, whole archive (1 thread, {tiles} of {} tiles, in order, once): {:.2} ns/pixel \
         ({} runs, {:.2} ns each)",
        files.len(),
        seconds * 1e9 / pixels as f64,
        keys.len(),
        seconds * 1e9 / keys.len().max(1) as f64,
    );
}

/// The keys ([`color_key`]) of a tile's texel pixels whose colour differs
/// from their left neighbour's, row by row.
fn fresh_texel_keys(layout: PixelLayout, rows: &[Vec<u8>]) -> Vec<u32> {
    let mut keys = Vec::new();
    for row in rows {
        let mut left = u32::MAX;
        for pixel in row.chunks_exact(layout.bytes_per_pixel()) {
            let color = layout.pack(pixel);
            if color != 0x000FFF && color != left {
                keys.push(color_key(color));
            }
            left = color;
        }
    }
    keys
}

/// The per-part tally with solid angles on the same decoded rows (one
/// thread): the AVX-512 kernel tallying parts in its own pass against the
/// same kernel followed by the separate pass, and the tallies compared.
fn parts_alone(
    tiles: &[(PixelLayout, Vec<Vec<u8>>)],
    pixels: usize,
    classifier: &Classifier,
    lookup: &PartLookup,
) {
    if Kernel::supported() < Kernel::Avx512 {
        return;
    }
    // A 107° eye of 5 × 5 tiles of 1284 × 1620, the tiles at its centre.
    let projection = EyeProjection::new(107.0, [5 * 1284, 5 * 1620]).unwrap();
    let view = TileView { projection, origin: [2 * 1284, 2 * 1620] };
    let strays = AtomicColorSet::new();
    let mut seen = SeenSet::new();
    let mut tallies = Vec::new();
    let mut time = |fused: bool| {
        let mut tally = PartPixels::new(lookup);
        let seconds = best_of(3, || {
            tally = PartPixels { view: Some(view), ..PartPixels::new(lookup) };
            let mut by_class = [0u64; 3];
            for (layout, rows) in tiles {
                let scan = RowScan::new(Kernel::Avx512, *layout, classifier);
                let scan = if fused { scan } else { scan.with_separate_parts() };
                let mut parts = PartRows::new(scan, *layout, classifier, lookup, &mut tally);
                for (y, row) in rows.iter().enumerate() {
                    parts.scan(row, y as u32, &mut seen, &strays, &mut by_class);
                }
                seen.clear();
            }
            black_box(by_class);
        });
        tallies.push(tally);
        seconds * 1e9 / pixels as f64
    };
    let (separate, fused) = (time(false), time(true));
    println!(
        "  avx512 kernel + per-part tally (1 thread, decoded rows, with solid angles): separate pass {separate:5.2} ns/pixel, fused {fused:5.2}: ratio fused / separate {:.3}; tallies identical: {}",
        fused / separate,
        tallies[0] == tallies[1]
    );
    assert_eq!(tallies[0], tallies[1], "the fused tally differs from the separate pass's");
}

/// 12 tiles spread over the archive (an approach changes from frame to
/// frame).
fn sampled_tiles(files: &[PathBuf]) -> Vec<PathBuf> {
    files.iter().step_by(files.len().div_ceil(12).max(1)).cloned().collect()
}

/// `files` decoded, kept in memory (1284×1620×3 bytes each).
fn decoded_tiles(files: &[PathBuf]) -> Vec<(PixelLayout, Vec<Vec<u8>>)> {
    files
        .iter()
        .map(|path| {
            let bytes = read_file(path).unwrap();
            let mut reader = RowReader::new(path, &bytes).unwrap();
            let mut rows = Vec::new();
            while let Some(row) = reader.next_row().unwrap() {
                rows.push(row.to_vec());
            }
            (reader.layout(), rows)
        })
        .collect()
}

fn main() {
    let args = parse_args();
    if let Some((list, decoder)) = &args.decode_files {
        let files: Vec<PathBuf> = std::fs::read_to_string(list).unwrap().lines().map(PathBuf::from).collect();
        println!("{}", decoder.decode(&files));
        return;
    }
    let temporary = tempfile::tempdir().unwrap();
    let mut archives = args.archives.clone();
    if archives.is_empty() {
        archives.push(generate_archive(
            &args,
            &args.keep.clone().unwrap_or_else(|| temporary.path().join("archive")),
        ));
        archives.extend(args.also.iter().cloned());
    }
    for archive in &archives {
        println!("\n== {}", archive.display());
        bench_archive(&args, archive, temporary.path());
    }
}

/// Every figure for one archive.
fn bench_archive(args: &Args, archive: &Path, scratch: &Path) {
    let files = object_tiles(archive);
    let pixels: u64 = files.iter().map(|p| pixels_of(p)).sum();
    let palette = Fcsp::canonical([4096, 4096]).unwrap();
    let classifier = Classifier::new(&palette, &[0x000FFF]).unwrap();
    let lookup = archive_lookup(archive, &palette);
    if args.processes_only {
        whole_processes(archive, &files, scratch);
        return;
    }
    if args.kernels_only {
        let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        one_thread.install(|| kernels_alone(&files, &classifier, lookup.as_ref()));
        return;
    }
    // The whole job first (so peak memory is ours alone; the listing above
    // only read headers and decoded rows one at a time).
    let options = AnalyzeOptions { archive: archive.to_path_buf(), ..Default::default() };
    whole_job(&options);
    // The ceiling: the png crate decoding the same tiles (the png crate
    // alone, as the issue measures it); and ufcsr's own decoder alone.
    let decode = best_of(3, || {
        black_box(Decoder::PngCrate.decode(&files));
    });
    let own_decode = best_of(3, || {
        black_box(Decoder::Ufcsr.decode(&files));
    });
    let megapixels = pixels as f64 / 1e6;
    counting_stage_against_decoding(&options, [megapixels / decode, megapixels / own_decode]);
    whole_processes(archive, &files, scratch);
    let count = best_of(3, || {
        black_box(ours(&files, &classifier));
    });
    against_decode(&files, pixels, [decode, own_decode, count]);
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    one_thread.install(|| kernels_alone(&files, &classifier, lookup.as_ref()));
}

/// The archive's part lookup, from its `parts.csv` and `pidt.png` (none
/// where it has no PIdT).
fn archive_lookup(archive: &Path, palette: &Fcsp) -> Option<PartLookup> {
    let legend = Legend::load(&archive.join("parts.csv")).ok()?;
    let pidt = Pidt::load(&archive.join("pidt.png"), &legend, [4096, 4096]).ok()?;
    Some(PartLookup::new(palette, Some((&legend, &pidt)), &[0x000FFF]))
}

/// The counting stage of `analyze()` (its `timings.count_seconds`: decode,
/// count and, by default, the per-part tables) in decoded Mpixel/s against
/// decoding the same tiles alone (`[png crate, ufcsr's decoder]`, Mpixel/s);
/// best of 3 each, alternated.
fn counting_stage_against_decoding(options: &AnalyzeOptions, [decode_rate, own_rate]: [f64; 2]) {
    let with_frames = AnalyzeOptions { frames: true, ..options.clone() };
    let count_only = AnalyzeOptions { texel_area: false, ..with_frames.clone() };
    let (mut framed, mut plain, mut counted) = (0.0f64, 0.0f64, 0.0f64);
    let (mut framed_whole, mut plain_whole, mut counted_whole) =
        (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    for _ in 0..3 {
        for (options, rate, whole) in [
            (&with_frames, &mut framed, &mut framed_whole),
            (&count_only, &mut counted, &mut counted_whole),
            (options, &mut plain, &mut plain_whole),
        ] {
            let start = Instant::now();
            let analysis = analyze(options, None).unwrap();
            *whole = whole.min(start.elapsed().as_secs_f64());
            *rate = rate.max(analysis.timings.decoded_megapixels_per_second);
        }
    }
    println!(
        "counting stage (decode + count), decoded Mpixel/s, best of 3, against decode only with the png crate \
         {decode_rate:.1} (the ceiling) and with ufcsr's own decoder {own_rate:.1}:"
    );
    println!(
        "  default (per-part tables, frames.csv)  {framed:8.1}  ratio {:.2}  (target ≥ 0.75); against ufcsr's decoder {:.2}",
        framed / decode_rate,
        framed / own_rate
    );
    println!(
        "  default with --texel-area off          {counted:8.1}  ratio {:.2}; against ufcsr's decoder {:.2}",
        counted / decode_rate,
        counted / own_rate
    );
    println!(
        "  --frames-csv off                       {plain:8.1}  ratio {:.2}  (target ≥ 0.90); against ufcsr's decoder {:.2}",
        plain / decode_rate,
        plain / own_rate
    );
    println!(
        "  analyze() with frames.csv / without: {:.3} ({framed_whole:.3} s vs {plain_whole:.3} s)",
        framed_whole / plain_whole
    );
    println!(
        "  analyze() default (per-texel area where the projection is known) / --texel-area off: {:.3} \
         ({framed_whole:.3} s vs {counted_whole:.3} s)",
        framed_whole / counted_whole
    );
}

/// The `ufcsr-analyze` binary of the same profile (built by the command-line
/// crate, which this bench's package cannot name: `scripts/bench.sh` builds it
/// first with `cargo build --release -p ufcsr-cli`): beside `deps/`, where
/// this bench runs from.
fn analyzer_binary() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().and_then(Path::parent).unwrap();
    let binary = profile_dir.join(format!("ufcsr-analyze{}", std::env::consts::EXE_SUFFIX));
    assert!(
        binary.is_file(),
        "{} is missing: build it first (cargo build --release -p ufcsr-cli, as scripts/bench.sh does)",
        binary.display()
    );
    binary
}

/// The whole `ufcsr-analyze` process (default options, result set
/// written) against a whole process that decodes the same tiles and nothing
/// else, alternated, 3 pairs; median of the pairs' ratios. Peak memory from
/// `/usr/bin/time` when it is there.
fn whole_processes(archive: &Path, files: &[PathBuf], scratch: &Path) {
    let list = scratch.join("decode-files.txt");
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    std::fs::write(&list, names.join("\n")).unwrap();
    let out = scratch.join("results");
    let ufcsr = [
        analyzer_binary().display().to_string(),
        archive.display().to_string(),
        "--out".into(),
        out.display().to_string(),
        "-q".into(),
    ];
    let mut count_only = ufcsr.to_vec();
    count_only.extend(["--texel-area".into(), "off".into()]);
    let decode = |flag: &str| {
        [std::env::current_exe().unwrap().display().to_string(), flag.into(), list.display().to_string()]
    };
    let (png_crate, own) = (decode("--decode-files"), decode("--decode-files-ufcsr"));
    let (mut ratios, mut own_ratios, mut peak) = (Vec::new(), Vec::new(), 0.0f64);
    let (mut area_cpu_ratios, mut area_wall_ratios, mut cpu_ceiling_ratios) =
        (Vec::new(), Vec::new(), Vec::new());
    let mut walls = [Vec::new(), Vec::new(), Vec::new()];
    let mut count_cpus = Vec::new();
    let pixels: u64 = files.iter().map(|p| pixels_of(p)).sum();
    for _ in 0..5 {
        let _ = std::fs::remove_dir_all(&out);
        let (ufcsr_wall, ufcsr_peak, ufcsr_cpu) = run_process(&ufcsr, scratch);
        let (decode_wall, _, decode_cpu) = run_process(&png_crate, scratch);
        let _ = std::fs::remove_dir_all(&out);
        let (count_wall, _, count_cpu) = run_process(&count_only, scratch);
        let (own_wall, _, _) = run_process(&own, scratch);
        area_cpu_ratios.push(ufcsr_cpu / count_cpu);
        count_cpus.push(count_cpu);
        area_wall_ratios.push(ufcsr_wall / count_wall);
        cpu_ceiling_ratios.push(decode_cpu / ufcsr_cpu);
        ratios.push(decode_wall / ufcsr_wall);
        own_ratios.push(own_wall / ufcsr_wall);
        for (list, wall) in walls.iter_mut().zip([ufcsr_wall, decode_wall, own_wall]) {
            list.push(wall);
        }
        peak = peak.max(ufcsr_peak);
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let [ufcsr_walls, decode_walls, own_walls] = walls;
    println!(
        "whole process: ufcsr analyze (default) {:.3} s, decode-only process (png crate) {:.3} s: ratio {:.2} (target ≥ 0.60), median of 5 rounds; ufcsr analyze peak {} (target ≤ 512 MiB)",
        median(ufcsr_walls),
        median(decode_walls),
        median(ratios),
        if peak > 0.0 { format!("{peak:.0} MiB") } else { "not measured (no /usr/bin/time)".into() }
    );
    println!(
        "  against a decode-only process with ufcsr's own decoder ({:.3} s): ratio {:.2}",
        median(own_walls),
        median(own_ratios)
    );
    println!(
        "  default / --texel-area off (the per-texel angular area's cost): CPU {:.3} (target ≤ 1.2), wall {:.3}; \
         decode-only / default CPU {:.2}; medians of 5 alternated rounds (CPU = user + sys)",
        median(area_cpu_ratios),
        median(area_wall_ratios),
        median(cpu_ceiling_ratios)
    );
    let count_ns = median(count_cpus) * 1e9 / pixels.max(1) as f64;
    println!(
        "  --texel-area off: {count_ns:.2} ns of CPU per decoded pixel, so the 1.2× target leaves the area \
         {:.2} ns/pixel (compare the angular-area floor of --kernels: one add per texel run, nothing else)",
        0.2 * count_ns
    );
}

/// Runs `command` (program and arguments) to the end: wall seconds, peak
/// resident MiB and CPU seconds, user + sys (both 0 without `/usr/bin/time`).
fn run_process(command: &[String], scratch: &Path) -> (f64, f64, f64) {
    let time = Path::new("/usr/bin/time");
    let report = scratch.join("time.txt");
    let mut process = if time.exists() {
        let mut p = std::process::Command::new(time);
        p.args(["-f", "%M %U %S", "-o"]).arg(&report).args(command);
        p
    } else {
        let mut p = std::process::Command::new(&command[0]);
        p.args(&command[1..]);
        p
    };
    let start = Instant::now();
    let status = process.stdout(std::process::Stdio::null()).status().unwrap();
    let wall = start.elapsed().as_secs_f64();
    assert!(status.success(), "{command:?} failed");
    let report = std::fs::read_to_string(&report).unwrap_or_default();
    let fields: Vec<f64> = report.split_whitespace().filter_map(|t| t.parse().ok()).collect();
    match fields[..] {
        [peak_kib, user, sys] => (wall, peak_kib / 1024.0, user + sys),
        _ => (wall, 0.0, 0.0),
    }
}

/// Writes the generated realistic archive into `dir`.
fn generate_archive(args: &Args, dir: &Path) -> PathBuf {
    let spec = ArchiveSpec { frames: args.frames, object_block: args.block, ..ArchiveSpec::default() };
    let start = Instant::now();
    let summary = write_archive(dir, &spec).unwrap();
    if args.projection {
        add_projection(dir, &spec);
    }
    println!(
        "generated {} tiles ({} with the vehicle, 1284×1620), {:.1} MiB, in {:.1} s",
        summary.tiles,
        summary.object_tiles,
        summary.bytes as f64 / (1 << 20) as f64,
        start.elapsed().as_secs_f64()
    );
    dir.to_path_buf()
}

/// Gives the generated archive's manifest the eyes' projection and fps
/// (`rig.settings`: 107° horizontal, 60 fps, the eye and its tiling), as a
/// capture's has.
fn add_projection(dir: &Path, spec: &ArchiveSpec) {
    let path = dir.join("manifest.json");
    let mut manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    manifest["rig"] = serde_json::json!({
        "settings": {
            "fps": 60.0,
            "horizontal_fov_deg": 107.0,
            "eye_pixels": [spec.cols * spec.tile_width, spec.rows * spec.tile_height],
            "tiles": [spec.cols, spec.rows],
        },
        "tile_pixels": [spec.tile_width, spec.tile_height],
    });
    std::fs::write(&path, serde_json::to_string_pretty(&manifest).unwrap()).unwrap();
}

/// The same tiles for every contender: the archive's own images (the
/// manifest's tiles; never the PIdT) that are not all background.
fn object_tiles(archive: &Path) -> Vec<PathBuf> {
    let listed = match ufcsr::Manifest::load_from_dir(archive).unwrap() {
        Some(manifest) => ufcsr::Archive::from_manifest(archive, &manifest).unwrap(),
        None => ufcsr::Archive::scan_folder(archive, &[], [4096, 4096]).unwrap(),
    };
    listed.images.into_iter().map(|image| image.path).filter(|path| !is_empty_tile(path)).collect()
}

/// `analyze()` on the whole archive: images per second and peak memory.
fn whole_job(options: &AnalyzeOptions) {
    let start = Instant::now();
    let analysis = analyze(options, None).unwrap();
    let whole = start.elapsed().as_secs_f64();
    let rss = peak_rss_mib();
    let images = &analysis.result.images;
    println!(
        "analyze(): {} images ({} trimmed, {} decoded) in {:.3} s = {:.0} images/s; peak RSS of this bench process so far {:.0} MiB",
        images.found,
        images.trimmed,
        images.decoded,
        whole,
        images.found as f64 / whole,
        rss
    );
}

/// ufcsr's decode + count against the decode-only ceiling (best times
/// `[png crate decode, ufcsr's decode, count]` of `files`, `pixels` in all).
fn against_decode(files: &[PathBuf], pixels: u64, [decode, own_decode, count]: [f64; 3]) {
    let megapixels = pixels as f64 / 1e6;
    let threads = rayon::current_num_threads();
    let kernel = ufcsr::Kernel::selected().name();
    println!("{} object tiles, {:.1} Mpixel, {} threads, {kernel} kernels", files.len(), megapixels, threads);
    println!("  decode only (ceiling)      {:8.1} Mpixel/s (the png crate)", megapixels / decode);
    println!(
        "  decode only, ufcsr's reader {:7.1} Mpixel/s (one inflate, Adler-32 and CRCs checked): {:.2}x the png crate",
        megapixels / own_decode,
        decode / own_decode
    );
    println!(
        "  ufcsr decode + count       {:8.1} Mpixel/s (scan_image, tiles read whole)",
        megapixels / count
    );
    println!(
        "  ratio ufcsr / decode-only   {:6.2}  (the kernels alone: no per-part pass, no trim)",
        decode / count
    );
    println!(
        "  decode only, per thread      {:5.2} ns/pixel (png crate), {:.2} (ufcsr's reader)",
        decode * threads as f64 * 1e9 / pixels as f64,
        own_decode * threads as f64 * 1e9 / pixels as f64
    );
}

fn pixels_of(path: &Path) -> u64 {
    let bytes = read_file(path).unwrap();
    let reader = RowReader::new(path, &bytes).unwrap();
    u64::from(reader.width()) * u64::from(reader.height())
}

/// True for an all-background tile (decoded once here, outside the timings).
fn is_empty_tile(path: &Path) -> bool {
    let bytes = read_file(path).unwrap();
    let mut reader = RowReader::new(path, &bytes).unwrap();
    let layout = reader.layout();
    while let Some(row) = reader.next_row().unwrap() {
        if row.chunks_exact(layout.bytes_per_pixel()).any(|p| layout.pack(p) != 0x000FFF) {
            return false;
        }
    }
    true
}
