//! The starts of a multistart: points spread over the search box (a Halton sequence or a
//! grid), ranked by their cost, and the best of them that lie apart from each other.

/// Radical inverse of `i` in base `b`: the `i`-th point of the van der Corput sequence in
/// base `b`, a coordinate of the Halton sequence (Halton 1960).
pub fn halton(mut i: usize, b: usize) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f /= b as f64;
        r += f * (i % b) as f64;
        i /= b;
    }
    r
}

/// The bases of the Halton sequence's coordinates (the first primes): at most this many
/// dimensions.
pub const HALTON_PRIMES: [usize; 10] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29];

/// The Halton points of indices 1..=`count` in the unit cube of `dim` ≤ 10 dimensions
/// (coordinate d in base [`HALTON_PRIMES`]`[d]`); index 0, the origin, is left out.
pub fn halton_points(count: usize, dim: usize) -> Vec<Vec<f64>> {
    (1..=count)
        .map(|i| (0..dim).map(|d| halton(i, HALTON_PRIMES[d])).collect())
        .collect()
}

/// `n` ≥ 2 equally spaced values from `lo` to `hi`: lo + (hi − lo)·j/(n − 1).
pub fn axis(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|j| lo + (hi - lo) * j as f64 / (n - 1) as f64)
        .collect()
}

/// The grid of all combinations of the axes' values, the first axis outermost.
pub fn grid(axes: &[Vec<f64>]) -> Vec<Vec<f64>> {
    axes.iter().fold(vec![Vec::new()], |pts, ax| {
        pts.iter()
            .flat_map(|p| {
                ax.iter().map(move |&v| {
                    let mut q = p.clone();
                    q.push(v);
                    q
                })
            })
            .collect()
    })
}

/// The points with their costs, cheapest first (a stable sort: equal costs keep their order).
pub fn ranked(mut points: Vec<(Vec<f64>, f64)>) -> Vec<(Vec<f64>, f64)> {
    points.sort_by(|a, b| a.1.total_cmp(&b.1));
    points
}

/// The starts of the local searches: in the order of `ranked` (cheapest first), each point
/// whose cost `admit`s it and that is `far` from every start taken before, up to `max`.
pub fn distinct_starts(
    ranked: &[(Vec<f64>, f64)],
    max: usize,
    admit: impl Fn(f64) -> bool,
    far: impl Fn(&[f64], &[f64]) -> bool,
) -> Vec<Vec<f64>> {
    let mut starts: Vec<Vec<f64>> = Vec::new();
    for (u, v) in ranked {
        if starts.len() >= max {
            break;
        }
        if admit(*v) && starts.iter().all(|s| far(s, u)) {
            starts.push(u.clone());
        }
    }
    starts
}

/// The Euclidean distance |a − b|.
pub fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}
