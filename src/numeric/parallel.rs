//! What the parallel loops over angles and scenarios share, so that their answers do not
//! depend on the thread count: results collected in order with the first failure in that
//! order ([`ordered`]), and values remembered by angle across threads ([`AngleMemo`]).

use rayon::prelude::*;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::Mutex;

/// The items of `it` in order (a `Vec` collects a parallel iterator in its order), or the
/// first error in that order. (Collecting a parallel iterator straight into a `Result`
/// returns whichever error a thread met first: another message from run to run where
/// several items fail.)
pub fn ordered<T: Send, E: Send>(
    it: impl ParallelIterator<Item = Result<T, E>>,
) -> Result<Vec<T>, E> {
    it.collect::<Vec<_>>().into_iter().collect()
}

/// Values by angle (θ's bits), made once and shared by every thread: what a scan, its
/// refinement and the certificate ask for again at the same angles.
#[derive(Debug)]
pub struct AngleMemo<T>(Mutex<ByBits<T>>);

/// A map by θ's bits.
type ByBits<T> = HashMap<u64, T, BuildHasherDefault<BitsHasher>>;

impl<T> Default for AngleMemo<T> {
    fn default() -> Self {
        AngleMemo(Mutex::new(HashMap::default()))
    }
}

/// The hash of one u64 (θ's bits) in a few operations: SplitMix64's finaliser,
/// z = (x ⊕ x≫30)·0xbf58476d1ce4e5b9, z = (z ⊕ z≫27)·0x94d049bb133111eb, z ⊕ z≫31, which
/// spreads every input bit over the high bits (the table's tags) and the low (its buckets).
/// The standard SipHash, made to resist keys chosen by an adversary, which angles are not,
/// was 7 % of a shape search's candidate (issue 36).
#[derive(Debug, Default, Clone, Copy)]
pub struct BitsHasher(u64);

impl Hasher for BitsHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = self.0.rotate_left(8) ^ u64::from(b);
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 ^= x;
    }

    fn finish(&self) -> u64 {
        let z = (self.0 ^ (self.0 >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        let z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

impl<T: Clone> AngleMemo<T> {
    /// The value at θ, made by `make` the first time.
    pub fn get_or(&self, theta: f64, make: impl FnOnce() -> T) -> T {
        self.try_get_or(theta, || Some(make()))
            .expect("make gave a value")
    }

    /// The value at θ, made by `make` the first time; a `None` from `make` is not kept
    /// (asked again, it is made again).
    pub fn try_get_or(&self, theta: f64, make: impl FnOnce() -> Option<T>) -> Option<T> {
        let key = theta.to_bits();
        if let Some(v) = self.lock().get(&key) {
            return Some(v.clone());
        }
        let v = make()?;
        self.lock().insert(key, v.clone());
        Some(v)
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, ByBits<T>> {
        self.0.lock().expect("no panic holds it")
    }
}
