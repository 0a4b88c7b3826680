//! What the parallel loops over angles and scenarios share, so that their answers do not
//! depend on the thread count: results collected in order with the first failure in that
//! order ([`ordered`]), and values remembered by angle across threads ([`AngleMemo`]).

use rayon::prelude::*;
use std::collections::HashMap;
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
pub struct AngleMemo<T>(Mutex<HashMap<u64, T>>);

impl<T> Default for AngleMemo<T> {
    fn default() -> Self {
        AngleMemo(Mutex::new(HashMap::new()))
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

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<u64, T>> {
        self.0.lock().expect("no panic holds it")
    }
}
