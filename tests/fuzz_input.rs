//! A bounded-time mutation fuzzer over the shipped scenes (`scenes/*.toml`) and meshes
//! (`scenes/meshes/*.inp`, `*.msh`): no input may make `Scene::parse` or `Scene::load` panic.
//! An allocation that aborts kills the test process, which fails the test too.
//!
//! Each case edits one input a few times: a number replaced by an extreme value (0, -1,
//! 1e308, 1e-320, NaN-ish text, 2147483648, 9223372036854775807, a huge integer, ...), two
//! numbers swapped, a line deleted or duplicated, or (in meshes and decks) 4 or 8 bytes
//! overwritten by an extreme binary value, a blank card, an `*END` with cards after it, a
//! data card (an id) copied elsewhere, or a keyword's block given twice. A scene is parsed as if it were the shipped file (its meshes
//! resolve against `scenes/`); a mesh is written to a temporary folder beside a copy of a
//! scene that uses it, and that scene is loaded. No simulation runs.
//!
//! Deterministic: case `k` draws from its own xorshift generator, seeded from the run's seed
//! (`IMPACT_FUZZ_SEED`, default [`DEFAULT_SEED`], printed) and `k`, so `IMPACT_FUZZ_CASE=k`
//! replays one case alone. `IMPACT_FUZZ_SECONDS` (default 20) bounds the wall time and
//! `IMPACT_FUZZ_CASES` (default 1,000,000) the number of cases. Before each case its seed,
//! number and edits are written to `fuzz_input/current_case.txt` in the target's temporary
//! folder, so that a case which aborts the process (an allocation failure) can be named.

mod common;
use common::repo;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use impact::scene::Scene;

const DEFAULT_SEED: u64 = 20_261_123;

/// Numbers put in place of a number of the text.
const TEXT_VALUES: &[&str] = &[
    "0",
    "-1",
    "1",
    "1e308",
    "-1e308",
    "1e-320",
    "1e400",
    "nan",
    "NaN",
    "-nan",
    "inf",
    "-inf",
    "1.#QNAN",
    "2147483647",
    "2147483648",
    "-2147483649",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "123456789012345678901234567890",
    "0.5",
    "-0",
];

/// Values written over 4 or 8 bytes of a mesh, little-endian.
const BINARY_VALUES: &[u64] = &[
    0,
    1,
    u64::MAX,
    1 << 31,
    1 << 32,
    i64::MAX as u64,
    1 << 63,
    0x7FF8_0000_0000_0000, // NaN
    0x7FEF_FFFF_FFFF_FFFF, // f64::MAX
    0x7FF0_0000_0000_0000, // infinity
    0x0000_0000_0000_0001, // the smallest subnormal
];

/// xorshift64* seeded through splitmix64 (never zero).
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        Rng((z ^ (z >> 31)).max(1))
    }

    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// A file to mutate: a scene, or a mesh with the scene that loads it.
struct Input {
    /// Relative to the repository, for messages.
    name: String,
    bytes: Vec<u8>,
    /// For a mesh: its file name and the text of a scene whose `mesh` key names
    /// `meshes/<file name>`.
    mesh: Option<(String, String)>,
    /// A deck run as it stands (`impact run model.inp`).
    deck: bool,
}

fn files(dir: &Path, ext: &[&str]) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("shipped folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| {
            p.extension()
                .is_some_and(|e| ext.contains(&e.to_string_lossy().as_ref()))
        })
        .collect();
    v.sort();
    v
}

/// The `meshes/...` file a scene text names in its `mesh` key, if any.
fn mesh_of(scene: &str) -> Option<&str> {
    let start = scene.find("mesh = \"meshes/")? + "mesh = \"".len();
    let len = scene[start..].find('"')?;
    Some(&scene[start..start + len])
}

fn inputs() -> Vec<Input> {
    let scenes_dir = repo().join("scenes");
    let scenes: Vec<(String, String)> = files(&scenes_dir, &["toml"])
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).expect("scene"))
        })
        .collect();
    let mut v: Vec<Input> = scenes
        .iter()
        .map(|(name, text)| Input {
            name: format!("scenes/{name}"),
            bytes: text.clone().into_bytes(),
            mesh: None,
            deck: false,
        })
        .collect();
    for p in files(&scenes_dir, &["inp", "k"]) {
        v.push(Input {
            name: format!("scenes/{}", p.file_name().unwrap().to_string_lossy()),
            bytes: std::fs::read(&p).expect("deck"),
            mesh: None,
            deck: true,
        });
    }
    for p in files(&scenes_dir.join("meshes"), &["inp", "msh"]) {
        let file = p.file_name().unwrap().to_string_lossy().into_owned();
        let ext = p.extension().unwrap().to_string_lossy().into_owned();
        let wanted = format!("meshes/{file}");
        // a scene that names this mesh, or failing that one that names a mesh of its kind
        let host = scenes
            .iter()
            .find(|(_, t)| mesh_of(t) == Some(&wanted))
            .map(|(_, t)| t.clone())
            .or_else(|| {
                scenes.iter().find_map(|(_, t)| {
                    let m = mesh_of(t)?;
                    m.ends_with(&format!(".{ext}"))
                        .then(|| t.replacen(m, &wanted, 1))
                })
            })
            .unwrap_or_else(|| panic!("no scene loads a .{ext} mesh"));
        v.push(Input {
            name: format!("scenes/{wanted}"),
            bytes: std::fs::read(&p).expect("mesh"),
            mesh: Some((file, host)),
            deck: false,
        });
    }
    v
}

/// Byte ranges of the numbers in `b`: a digit run (with sign, point and exponent) that does
/// not continue a word.
fn numbers(b: &[u8]) -> Vec<(usize, usize)> {
    let word = |c: u8| c.is_ascii_alphanumeric() || c == b'_' || c == b'.';
    let part = |c: u8| c.is_ascii_digit() || matches!(c, b'.' | b'e' | b'E' | b'+' | b'-');
    let mut v = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit()
            || (matches!(b[i], b'-' | b'+' | b'.') && b.get(i + 1).is_some_and(u8::is_ascii_digit));
        if starts && (i == 0 || !word(b[i - 1])) {
            let mut j = i + 1;
            while j < b.len() && part(b[j]) {
                j += 1;
            }
            v.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    v
}

/// Byte ranges of the lines of `b` (each with its `\n`).
fn lines(b: &[u8]) -> Vec<(usize, usize)> {
    let mut v = Vec::new();
    let mut start = 0;
    for (i, &c) in b.iter().enumerate() {
        if c == b'\n' {
            v.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < b.len() {
        v.push((start, b.len()));
    }
    v
}

/// One of `nums` (not empty): any, one in the two lines after a keyword or section line
/// (`*NODE`, `$Nodes`: where the counts and `GENERATE` ranges are), or the first of a line
/// (block headers, ids).
fn pick(rng: &mut Rng, b: &[u8], nums: &[(usize, usize)]) -> (usize, usize) {
    let ls = lines(b);
    let chosen: Vec<(usize, usize)> = match rng.below(3) {
        0 => Vec::new(),
        1 => {
            let windows: Vec<(usize, usize)> = ls
                .iter()
                .enumerate()
                .filter(|(_, (s, _))| matches!(b[*s], b'*' | b'$'))
                .map(|(k, &(_, e))| (e, ls.get(k + 2).map_or(b.len(), |l| l.1)))
                .collect();
            nums.iter()
                .copied()
                .filter(|&(s, _)| windows.iter().any(|&(ws, we)| (ws..we).contains(&s)))
                .collect()
        }
        _ => {
            let mut firsts = Vec::new();
            let mut k = 0;
            for &(ls, le) in &ls {
                while k < nums.len() && nums[k].0 < ls {
                    k += 1;
                }
                if k < nums.len() && nums[k].0 < le {
                    firsts.push(nums[k]);
                }
            }
            firsts
        }
    };
    if chosen.is_empty() {
        nums[rng.below(nums.len())]
    } else {
        chosen[rng.below(chosen.len())]
    }
}

fn line_of(b: &[u8], at: usize) -> usize {
    1 + b[..at.min(b.len())].iter().filter(|&&c| c == b'\n').count()
}

fn show(b: &[u8]) -> String {
    let s = String::from_utf8_lossy(&b[..b.len().min(60)]).into_owned();
    format!("{:?}{}", s, if b.len() > 60 { "..." } else { "" })
}

/// Applies one random mutation to `b`; returns what it did.
fn mutate(rng: &mut Rng, b: &mut Vec<u8>, mesh: bool) -> String {
    let kinds = if mesh { 9 } else { 4 };
    match rng.below(kinds) {
        5..=8 => deck_mutation(rng, b),
        0 | 1 => {
            let nums = numbers(b);
            if nums.is_empty() {
                return "nothing (no number)".into();
            }
            let (s, e) = pick(rng, b, &nums);
            let old = b[s..e].to_vec();
            if rng.below(2) == 0 {
                let new = TEXT_VALUES[rng.below(TEXT_VALUES.len())];
                b.splice(s..e, new.bytes());
                format!("line {}: number {} -> {new:?}", line_of(b, s), show(&old))
            } else {
                let (s2, e2) = pick(rng, b, &nums);
                if s2 == s {
                    return "nothing (swap with itself)".into();
                }
                let other = b[s2..e2].to_vec();
                let line2 = line_of(b, s2);
                let line1 = line_of(b, s);
                // the later range first, so the earlier one's offsets stay valid
                let (first, second) = if s < s2 {
                    ((s, e, &other), (s2, e2, &old))
                } else {
                    ((s2, e2, &old), (s, e, &other))
                };
                b.splice(second.0..second.1, second.2.iter().copied());
                b.splice(first.0..first.1, first.2.iter().copied());
                format!(
                    "line {line1}: number {} swapped with line {line2}: number {}",
                    show(&old),
                    show(&other)
                )
            }
        }
        2 => {
            let ls = lines(b);
            if ls.is_empty() {
                return "nothing (no line)".into();
            }
            let k = rng.below(ls.len());
            let (s, e) = ls[k];
            let old: Vec<u8> = b.drain(s..e).collect();
            format!("line {}: deleted {}", k + 1, show(&old))
        }
        3 => {
            let ls = lines(b);
            if ls.is_empty() {
                return "nothing (no line)".into();
            }
            let k = rng.below(ls.len());
            let (s, e) = ls[k];
            let copy = b[s..e].to_vec();
            b.splice(s..s, copy.iter().copied());
            format!("line {}: duplicated {}", k + 1, show(&copy))
        }
        _ => {
            // binary: often right after a section header, where the counts are
            let width = if rng.below(2) == 0 { 4 } else { 8 };
            if b.len() < width {
                return "nothing (too short)".into();
            }
            let headers: Vec<usize> = lines(b)
                .iter()
                .filter(|(s, _)| b[*s] == b'$')
                .map(|&(_, e)| e)
                .collect();
            let at = if rng.below(2) == 0 && !headers.is_empty() {
                headers[rng.below(headers.len())] + 4 * rng.below(12)
            } else {
                rng.below(b.len())
            }
            .min(b.len() - width);
            let value = BINARY_VALUES[rng.below(BINARY_VALUES.len())];
            b[at..at + width].copy_from_slice(&value.to_le_bytes()[..width]);
            format!(
                "byte {at} (line {}): {width} bytes <- {value:#x}",
                line_of(b, at)
            )
        }
    }
}

/// A deck's own mistakes: a blank card, an `*END` with cards after it, a data card (an id)
/// copied elsewhere, or a keyword's block (a section, a part, a set) given twice.
fn deck_mutation(rng: &mut Rng, b: &mut Vec<u8>) -> String {
    let ls = lines(b);
    if ls.is_empty() {
        return "nothing (no line)".into();
    }
    let (at, _) = ls[rng.below(ls.len())];
    let line = line_of(b, at);
    let starts = |s: usize, c: u8| b.get(s) == Some(&c);
    match rng.below(4) {
        0 => {
            b.splice(at..at, *b"\n");
            format!("line {line}: a blank card")
        }
        1 => {
            b.splice(at..at, *b"*END\n");
            format!("line {line}: *END, the rest after it")
        }
        2 => {
            let data: Vec<_> = ls
                .iter()
                .filter(|(s, _)| b[*s].is_ascii_digit() || b[*s] == b' ')
                .collect();
            if data.is_empty() {
                return "nothing (no data card)".into();
            }
            let (s, e) = *data[rng.below(data.len())];
            let copy = b[s..e].to_vec();
            b.splice(at..at, copy.iter().copied());
            format!("line {line}: a copy of the card {}", show(&copy))
        }
        _ => {
            let keys: Vec<usize> = (0..ls.len()).filter(|&k| starts(ls[k].0, b'*')).collect();
            if keys.is_empty() {
                return "nothing (no keyword)".into();
            }
            let k = keys[rng.below(keys.len())];
            let end = (k + 1..ls.len())
                .find(|&j| starts(ls[j].0, b'*'))
                .map_or(b.len(), |j| ls[j].0);
            let block = b[ls[k].0..end].to_vec();
            b.splice(at..at, block.iter().copied());
            format!(
                "line {line}: a copy of the block {}",
                show(&block[..block.len().min(60)])
            )
        }
    }
}

/// Runs one case: `Ok` whether the input is accepted or refused, `Err` with the panic's
/// message if it panicked.
fn run_case(input: &Input, bytes: &[u8], tmp: &Path) -> Result<bool, String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| match &input.mesh {
        None if input.deck => {
            let ext = Path::new(&input.name)
                .extension()
                .unwrap()
                .to_string_lossy();
            let deck = tmp.join(format!("deck.{ext}"));
            std::fs::write(&deck, bytes).expect("write deck");
            Scene::load(&deck).is_ok()
        }
        None => {
            let text = String::from_utf8_lossy(bytes);
            let path = repo().join(&input.name);
            Scene::parse(&text, &path).is_ok()
        }
        Some((file, host)) => {
            std::fs::write(tmp.join("meshes").join(file), bytes).expect("write mesh");
            let scene = tmp.join("scene.toml");
            std::fs::write(&scene, host).expect("write scene");
            Scene::load(&scene).is_ok()
        }
    }));
    outcome.map_err(|p| {
        p.downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "(a panic without a message)".into())
    })
}

fn env_u64(name: &str) -> Option<u64> {
    std::env::var(name).ok().and_then(|s| s.trim().parse().ok())
}

#[test]
fn mutated_scenes_and_meshes_never_panic() {
    let seed = env_u64("IMPACT_FUZZ_SEED").unwrap_or(DEFAULT_SEED);
    let seconds = env_u64("IMPACT_FUZZ_SECONDS").unwrap_or(20);
    let max_cases = env_u64("IMPACT_FUZZ_CASES").unwrap_or(1_000_000);
    let only = env_u64("IMPACT_FUZZ_CASE");
    eprintln!(
        "fuzz_input: seed {seed} (IMPACT_FUZZ_SEED), {seconds} s (IMPACT_FUZZ_SECONDS), at most {max_cases} cases (IMPACT_FUZZ_CASES)"
    );
    let inputs = inputs();
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz_input");
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(tmp.join("meshes")).expect("temporary folder");
    let current = tmp.join("current_case.txt");
    eprintln!(
        "fuzz_input: should the process abort, {} names the case",
        current.display()
    );

    let start = Instant::now();
    let budget = Duration::from_secs(seconds);
    let (mut ran, mut accepted) = (0u64, 0u64);
    let mut failures = Vec::new();
    let cases: Box<dyn Iterator<Item = u64>> = match only {
        Some(k) => Box::new(std::iter::once(k)),
        None => Box::new(0..max_cases),
    };
    for case in cases {
        if only.is_none() && start.elapsed() >= budget {
            break;
        }
        let mut rng = Rng::new(seed ^ case.wrapping_mul(0xD1B5_4A32_D192_ED03));
        let input = &inputs[rng.below(inputs.len())];
        let mut bytes = input.bytes.clone();
        let edits: Vec<String> = (0..1 + rng.below(3))
            .map(|_| mutate(&mut rng, &mut bytes, input.mesh.is_some() || input.deck))
            .collect();
        let what = format!("{}: {}", input.name, edits.join("; "));
        if only.is_some() {
            eprintln!("case {case}: {what}");
        }
        let replay = format!("IMPACT_FUZZ_SEED={seed} IMPACT_FUZZ_CASE={case}");
        std::fs::write(&current, format!("{replay}\n{what}\n")).expect("write the case");
        ran += 1;
        match run_case(input, &bytes, &tmp) {
            Ok(ok) => accepted += u64::from(ok),
            Err(panic) => {
                eprintln!("PANIC seed {seed} case {case}: {what}: {panic}");
                failures.push(format!(
                    "seed {seed} case {case} (replay: {replay}): {what}: panicked: {panic}"
                ));
            }
        }
    }
    eprintln!(
        "fuzz_input: {ran} cases in {:.1} s over {} inputs: {accepted} accepted, {} refused, {} panicked",
        start.elapsed().as_secs_f64(),
        inputs.len(),
        ran - accepted - failures.len() as u64,
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {ran} cases panicked:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Checkpoints and histories damaged at random: 1 to 4 bytes of `checkpoint.bin` flipped
/// anywhere, or the file cut at a random length, is refused by `Checkpoint::read` in every
/// case; a history cut inside the rows the checkpoint keeps, or with a byte of them changed,
/// is refused by the resume. Bounded by `IMPACT_FUZZ_SECONDS` (default 20) like the test
/// above, on the same seed.
#[test]
fn damaged_checkpoints_and_histories_never_resume() {
    use impact::checkpoint::Checkpoint;
    use impact::output::History;
    let text = std::fs::read_to_string(repo().join("scenes/two_bars.toml"))
        .unwrap()
        .replace("end_time = 0.4", "end_time = 0.2")
        + "\n[output]\ncheckpoint_every = 20\n";
    let scene = Scene::parse(&text, &repo().join("scenes/fuzz_checkpoint.toml")).unwrap();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz_checkpoint");
    let _ = std::fs::remove_dir_all(&dir);
    let opts = impact::run::RunOptions {
        out: Some(dir.clone()),
        device: Some(impact::scene::DeviceChoice::Cpu),
        quiet: true,
        ..Default::default()
    };
    impact::run::run(&scene, &opts).expect("the run completes");
    let model = impact::model::Model::from_scene(&scene).unwrap();
    let whole = std::fs::read(dir.join("checkpoint.bin")).unwrap();
    let c = Checkpoint::read(&dir, &scene).expect("the written checkpoint reads");
    let rows = c.tally.steps + 1;
    let time = 0.2;
    let history = std::fs::read(dir.join("history.csv")).unwrap();
    // the byte after the header and the kept rows
    let kept = (history.iter().enumerate())
        .filter(|(_, b)| **b == b'\n')
        .nth(rows)
        .map(|(i, _)| i + 1)
        .unwrap();
    let header = history.iter().position(|b| *b == b'\n').unwrap() + 1;
    let seed = env_u64("IMPACT_FUZZ_SEED").unwrap_or(DEFAULT_SEED);
    let seconds = env_u64("IMPACT_FUZZ_SECONDS").unwrap_or(20);
    let start = Instant::now();
    let mut cases = 0u64;
    while start.elapsed() < Duration::from_secs(seconds) && cases < 100_000 {
        let mut rng = Rng::new(seed ^ cases.wrapping_mul(0x9E37_79B9));
        cases += 1;
        // a damaged checkpoint
        let mut bytes = whole.clone();
        if rng.below(4) == 0 {
            bytes.truncate(rng.below(whole.len()));
        } else {
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(bytes.len());
                bytes[at] ^= 1 + rng.below(255) as u8;
            }
        }
        std::fs::write(dir.join("checkpoint.bin"), &bytes).unwrap();
        assert!(
            Checkpoint::read(&dir, &scene).is_err(),
            "case {cases}: a damaged checkpoint was read"
        );
        // a damaged history: cut inside the kept rows, or one of their bytes changed
        let mut h = history.clone();
        if rng.below(2) == 0 {
            h.truncate(header + rng.below(kept - header));
        } else {
            let at = header + rng.below(kept - header);
            let old = h[at];
            h[at] = match old {
                b'\n' => b',',
                b',' => b'\n',
                b'0'..=b'9' => b"x,\n.e-"[rng.below(6)],
                _ => b'#',
            };
        }
        std::fs::write(dir.join("history.csv"), &h).unwrap();
        let resumed = History::resume(&dir, &model, rows, time);
        if resumed.is_ok() {
            // only a change that leaves the kept rows whole rows of numbers, the last of the
            // checkpoint's step and time, may pass (a digit changed inside a value)
            let text = String::from_utf8_lossy(&h[header..]).into_owned();
            assert!(
                (text.lines().take(rows)).all(|l| l.split(',').all(|v| v.parse::<f64>().is_ok())),
                "case {cases}: a history with broken rows resumed: {:?}",
                String::from_utf8_lossy(&h[kept.saturating_sub(300).min(h.len())..])
            );
        }
    }
    std::fs::write(dir.join("checkpoint.bin"), &whole).unwrap();
    println!(
        "{cases} cases in {:.1} s: every damaged checkpoint refused, every history that resumed whole",
        start.elapsed().as_secs_f64()
    );
    assert!(cases > 0);
}
