//! The points of a plot: arcs as chords, and points thinned to what a
//! pixel can show.

/// Greatest angle of one chord when an arc is sampled (radians).
const ARC_STEP: f64 = std::f64::consts::PI / 36.0;

/// Chords of the arc from `a` to `b` around `c` (a full circle when the
/// ends meet), at most [`ARC_STEP`] each.
pub fn arc_points(a: [f64; 2], b: [f64; 2], c: [f64; 2], ccw: bool) -> Vec<[f64; 2]> {
    let r = (a[0] - c[0]).hypot(a[1] - c[1]);
    let start = (a[1] - c[1]).atan2(a[0] - c[0]);
    let end = (b[1] - c[1]).atan2(b[0] - c[0]);
    let tau = std::f64::consts::TAU;
    let mut sweep = if ccw { end - start } else { start - end };
    sweep = sweep.rem_euclid(tau);
    if sweep < 1e-12 {
        sweep = tau;
    }
    let n = ((sweep / ARC_STEP).ceil() as usize).max(1);
    let sign = if ccw { 1.0 } else { -1.0 };
    let mut out: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let t = start + sign * sweep * k as f64 / n as f64;
            [c[0] + r * t.cos(), c[1] + r * t.sin()]
        })
        .collect();
    out.push(b);
    out
}

/// Drops points closer than `eps` to the last one kept (the ends stay).
pub fn thin(points: &[[f64; 2]], eps: f64) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(points.len());
    for (k, p) in points.iter().enumerate() {
        let far = out
            .last()
            .is_none_or(|l| (l[0] - p[0]).hypot(l[1] - p[1]) > eps);
        if far || k + 1 == points.len() {
            out.push(*p);
        }
    }
    out
}
