//! The two content hashes of a batch: the **input hash** of a machine (its problem text, or
//! its fleet row with the template and header, and the cwsynth build), which says whether a
//! previous result is still the answer, and the **file hash** of a written result file,
//! which tells a whole file from a torn one at resume. Neither is cryptographic.

/// A 128-bit content hash being computed (two FNV-1a 64 streams), started with the cwsynth
/// version and a hash of its source (`CWSYNTH_SOURCE_HASH`, from `build.rs`), so a changed
/// program re-solves everything instead of keeping results the old code computed.
#[derive(Clone)]
pub(super) struct Hasher {
    a: u64,
    b: u64,
}

impl Hasher {
    /// A hash of the cwsynth build so far.
    pub(super) fn new() -> Hasher {
        let mut h = Hasher {
            a: 0xcbf2_9ce4_8422_2325,
            b: 0x6c62_272e_07bb_0142,
        };
        h.bytes(env!("CARGO_PKG_VERSION").as_bytes());
        h.bytes(b"\0");
        h.bytes(env!("CWSYNTH_SOURCE_HASH").as_bytes());
        h.bytes(b"\0");
        h
    }

    /// Adds raw bytes.
    pub(super) fn bytes(&mut self, bytes: &[u8]) {
        for &x in bytes {
            self.a = (self.a ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3);
            self.b = (self.b ^ x as u64 ^ 0x5a).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// One string of a sequence: its length, then its bytes (so no two sequences run together).
    pub(super) fn field(&mut self, s: &str) {
        self.bytes(&(s.len() as u64).to_le_bytes());
        self.bytes(s.as_bytes());
    }

    /// The hash so far, 32 hex digits.
    pub(super) fn hex(&self) -> String {
        format!("{:016x}{:016x}", self.a, self.b)
    }
}

/// The content hash of a problem file's text and the cwsynth build, hex.
pub fn content_hash(text: &str) -> String {
    let mut h = Hasher::new();
    h.bytes(text.as_bytes());
    h.hex()
}

/// The input hash of a problem file: its text and the bytes of every drawing it reads (each
/// `outline = { file = … }`, relative to the file's folder; a missing one hashes as such),
/// so a re-run notices an edited drawing as it notices an edited problem. A text that is no
/// TOML hashes as its text (its error row says why).
pub fn problem_hash(text: &str, path: &std::path::Path) -> String {
    let mut h = Hasher::new();
    h.bytes(text.as_bytes());
    h.drawings(text, path);
    h.hex()
}

impl Hasher {
    /// Adds the bytes of every drawing the TOML `text` of the file at `path` names
    /// (`outline.file`, relative to the file's folder), each with its name; nothing for a
    /// text that is no TOML.
    pub(super) fn drawings(&mut self, text: &str, path: &std::path::Path) {
        let Ok(doc) = text.parse::<toml::Table>() else {
            return;
        };
        let dir = path.parent().unwrap_or(std::path::Path::new("."));
        for (_, f) in drawings(&doc) {
            self.drawing(&f, dir);
        }
    }

    /// Adds one drawing's name and bytes, `file` read relative to `dir` (a missing one hashes
    /// as such).
    pub(super) fn drawing(&mut self, file: &str, dir: &std::path::Path) {
        self.field(file);
        match std::fs::read(dir.join(file)) {
            Ok(bytes) => {
                self.bytes(b"\x01");
                self.bytes(&(bytes.len() as u64).to_le_bytes());
                self.bytes(&bytes);
            }
            Err(_) => self.bytes(b"\x00"),
        }
    }
}

/// Every `outline.file` string of `table`, in key order, each with the dotted key of its
/// `outline` table (`mechanism.links.crank.outline`; an array's element as `key[i]`).
pub(super) fn drawings(table: &toml::Table) -> Vec<(String, String)> {
    let mut out = Vec::new();
    collect(table, "", &mut out);
    out
}

/// The drawings of the table whose dotted key is `at` (see [`drawings`]).
fn collect(t: &toml::Table, at: &str, out: &mut Vec<(String, String)>) {
    for (k, v) in t {
        let key = match at {
            "" => k.clone(),
            _ => format!("{at}.{k}"),
        };
        if k == "outline" {
            if let Some(f) = v.get("file").and_then(|f| f.as_str()) {
                out.push((key.clone(), f.to_string()));
            }
        }
        let tables: Vec<(String, &toml::Table)> = match v {
            toml::Value::Table(t) => vec![(key, t)],
            toml::Value::Array(a) => a
                .iter()
                .enumerate()
                .filter_map(|(i, v)| v.as_table().map(|t| (format!("{key}[{i}]"), t)))
                .collect(),
            _ => Vec::new(),
        };
        for (key, t) in tables {
            collect(t, &key, out);
        }
    }
}

/// A content hash of a result file, 128 bits in hex, to tell a whole file from a torn one at
/// resume: two multiply-rotate streams over 8-byte words (fast, not cryptographic), the
/// length folded in.
pub fn file_hash(bytes: &[u8]) -> String {
    let (mut a, mut b) = (0x9e37_79b9_7f4a_7c15u64, 0xc2b2_ae3d_27d4_eb4fu64);
    let mut words = bytes.chunks_exact(8);
    for w in words.by_ref() {
        let x = u64::from_le_bytes(w.try_into().expect("8 bytes"));
        a = (a ^ x).wrapping_mul(0xff51_afd7_ed55_8ccd).rotate_left(29);
        b = (b ^ x.rotate_left(32))
            .wrapping_mul(0xc4ce_b9fe_1a85_ec53)
            .rotate_left(31);
    }
    let mut tail = [0u8; 8];
    tail[..words.remainder().len()].copy_from_slice(words.remainder());
    let x = u64::from_le_bytes(tail) ^ ((bytes.len() as u64) << 3);
    a = (a ^ x).wrapping_mul(0xff51_afd7_ed55_8ccd);
    b = (b ^ x.rotate_left(32) ^ a).wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    a ^= a >> 33;
    b ^= b >> 29;
    format!("{a:016x}{b:016x}")
}
