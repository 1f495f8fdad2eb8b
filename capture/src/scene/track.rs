//! Keyframe tracks: vehicle position and yaw over time.
//!
//! Keys are stored the way Unity's `AnimationCurve` stores them — a value plus
//! an in and an out slope (units per second) — so scenarios exported from
//! Unity replay exactly. A segment between two keys is a cubic Hermite when
//! the left key has an out slope and the right key an in slope, and linear
//! otherwise (keys without slopes are "linear keys"). Before the first and
//! after the last key the curve holds its end value, like Unity's default
//! clamp wrap mode.

use glam::{DVec3, dvec3};
use serde::{Deserialize, Serialize};

use crate::error::{CaptureError, Result};

/// Largest time, value or slope a track key may have (metres, seconds, degrees).
pub(crate) const MAX_TRACK_MAGNITUDE: f64 = 1.0e6;

/// One key of an N-dimensional track.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Key<const N: usize> {
    /// Time in seconds.
    pub t: f64,
    /// Value at `t`.
    #[serde(with = "array_or_scalar")]
    pub value: [f64; N],
    /// Slope arriving at the key (per second); absent for a linear key.
    #[serde(default, skip_serializing_if = "Option::is_none", with = "opt_array_or_scalar")]
    pub in_slope: Option<[f64; N]>,
    /// Slope leaving the key (per second); absent for a linear key.
    #[serde(default, skip_serializing_if = "Option::is_none", with = "opt_array_or_scalar")]
    pub out_slope: Option<[f64; N]>,
}

impl<const N: usize> Key<N> {
    /// A linear key (no slopes).
    pub fn linear(t: f64, value: [f64; N]) -> Key<N> {
        Key { t, value, in_slope: None, out_slope: None }
    }

    /// A Hermite key with the same slope on both sides.
    pub fn smooth(t: f64, value: [f64; N], slope: [f64; N]) -> Key<N> {
        Key { t, value, in_slope: Some(slope), out_slope: Some(slope) }
    }
}

/// A track: keys sorted by time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Track<const N: usize> {
    pub keys: Vec<Key<N>>,
}

impl<const N: usize> Track<N> {
    /// Builds a track, rejecting empty tracks and unsorted or non-finite keys.
    pub fn new(keys: Vec<Key<N>>) -> Result<Track<N>> {
        let track = Track { keys };
        track.check()?;
        Ok(track)
    }

    /// Checks that there is a key, values and slopes are finite and of street
    /// scale ([`MAX_TRACK_MAGNITUDE`]), and that times strictly increase.
    pub fn check(&self) -> Result<()> {
        if self.keys.is_empty() {
            return Err(CaptureError::BadOptions("a track needs at least one key".into()));
        }
        for key in &self.keys {
            let finite = key.t.is_finite()
                && key.value.iter().all(|v| v.is_finite())
                && key.in_slope.iter().flatten().all(|v| v.is_finite())
                && key.out_slope.iter().flatten().all(|v| v.is_finite());
            if !finite {
                return Err(CaptureError::BadOptions(format!("track key at t={} is not finite", key.t)));
            }
            // Finite is not enough: 1e308 overflows to infinity in the Hermite
            // sums and ends as `null` in the manifest. A street scene fits
            // within ±1000 km and 1000 km/s (or degrees and degrees per second).
            let huge = |v: &f64| v.abs() > MAX_TRACK_MAGNITUDE;
            if key.t.abs() > MAX_TRACK_MAGNITUDE
                || key.value.iter().any(huge)
                || key.in_slope.iter().flatten().any(huge)
                || key.out_slope.iter().flatten().any(huge)
            {
                return Err(CaptureError::BadOptions(format!(
                    "track key at t={} has a time, value or slope beyond ±{MAX_TRACK_MAGNITUDE:e}: not a street scene",
                    key.t
                )));
            }
        }
        for pair in self.keys.windows(2) {
            if pair[1].t <= pair[0].t {
                return Err(CaptureError::BadOptions(format!(
                    "track key times must increase, but {} follows {}",
                    pair[1].t, pair[0].t
                )));
            }
        }
        Ok(())
    }

    /// The value at time `t`.
    pub fn eval(&self, t: f64) -> [f64; N] {
        let keys = &self.keys;
        let (Some(first), Some(last)) = (keys.first(), keys.last()) else {
            return [0.0; N];
        };
        if t <= first.t {
            return first.value;
        }
        if t >= last.t {
            return last.value;
        }
        // The segment whose right key is the first key after t.
        let right = keys.partition_point(|key| key.t <= t);
        let (k0, k1) = (&keys[right - 1], &keys[right]);
        let dt = k1.t - k0.t;
        let s = (t - k0.t) / dt;
        match (k0.out_slope, k1.in_slope) {
            (Some(m0), Some(m1)) => {
                let s2 = s * s;
                let s3 = s2 * s;
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = s3 - 2.0 * s2 + s;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = s3 - s2;
                std::array::from_fn(|i| {
                    h00 * k0.value[i] + h10 * dt * m0[i] + h01 * k1.value[i] + h11 * dt * m1[i]
                })
            }
            _ => std::array::from_fn(|i| k0.value[i] + s * (k1.value[i] - k0.value[i])),
        }
    }

    /// The slopes (per second) with which [`Track::eval`] arrives at and
    /// leaves key `k`: a Hermite segment's key slopes, a linear segment's
    /// secant, and 0 before the first and after the last key (the curve holds
    /// its end values). They differ where the motion's speed jumps.
    pub fn slopes_at(&self, k: usize) -> ([f64; N], [f64; N]) {
        let segment = |left: usize| -> ([f64; N], [f64; N]) {
            let (k0, k1) = (&self.keys[left], &self.keys[left + 1]);
            match (k0.out_slope, k1.in_slope) {
                (Some(out), Some(arriving)) => (out, arriving),
                _ => {
                    let secant = std::array::from_fn(|i| (k1.value[i] - k0.value[i]) / (k1.t - k0.t));
                    (secant, secant)
                }
            }
        };
        let arriving = if k == 0 || k >= self.keys.len() { [0.0; N] } else { segment(k - 1).1 };
        let leaving = if k + 1 >= self.keys.len() { [0.0; N] } else { segment(k).0 };
        (arriving, leaving)
    }

    /// True when every segment runs at constant speed: each key's slopes
    /// are its segments' secants (Unity's "Linear" tangents) or absent, to
    /// 1e-4 and the f32 rounding of values Unity stores (a few units of f32
    /// of the values, over the interval).
    pub fn is_piecewise_linear(&self) -> bool {
        self.keys.windows(2).all(|pair| {
            let dt = pair[1].t - pair[0].t;
            let secant: [f64; N] = std::array::from_fn(|i| (pair[1].value[i] - pair[0].value[i]) / dt);
            let rounding: [f64; N] = std::array::from_fn(|i| {
                4.0 * f64::from(f32::EPSILON) * pair[0].value[i].abs().max(pair[1].value[i].abs()) / dt
            });
            let near = |m: [f64; N]| {
                (0..N).all(|i| (m[i] - secant[i]).abs() <= 1e-4 * secant[i].abs() + rounding[i])
            };
            match (pair[0].out_slope, pair[1].in_slope) {
                (Some(out), Some(arriving)) => near(out) && near(arriving),
                _ => true,
            }
        })
    }

    /// Time of the last key.
    pub fn end_time(&self) -> f64 {
        self.keys.last().map_or(0.0, |key| key.t)
    }
}

/// A vehicle's motion: position (world metres, Z up) and yaw (degrees,
/// counter-clockwise from +X seen from above).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    pub position: Track<3>,
    pub yaw_deg: Track<1>,
}

/// Where the vehicle is at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    pub position: DVec3,
    pub yaw_deg: f64,
}

impl Motion {
    /// The pose at time `t`.
    pub fn pose(&self, t: f64) -> Pose {
        let [x, y, z] = self.position.eval(t);
        Pose { position: dvec3(x, y, z), yaw_deg: self.yaw_deg.eval(t)[0] }
    }

    /// Checks both tracks.
    pub fn check(&self) -> Result<()> {
        self.position.check()?;
        self.yaw_deg.check()
    }
}

/// A value that either stays put or follows a track, as a scene file
/// writes it: a fixed value (`[x, y, z]`, or a bare number for one
/// dimension) or a list of keys (`[{"t": 0, "value": …}, …]`).
#[derive(Debug, Clone, PartialEq)]
pub enum ValueOrTrack<const N: usize> {
    Fixed([f64; N]),
    Keys(Track<N>),
}

impl<const N: usize> ValueOrTrack<N> {
    /// The value at time `t`.
    pub fn eval(&self, t: f64) -> [f64; N] {
        match self {
            ValueOrTrack::Fixed(value) => *value,
            ValueOrTrack::Keys(track) => track.eval(t),
        }
    }

    /// Checks a track as [`Track::check`] does, and a fixed value against
    /// the same street-scale bound.
    pub fn check(&self) -> Result<()> {
        match self {
            ValueOrTrack::Keys(track) => track.check(),
            ValueOrTrack::Fixed(value) => {
                match value.iter().find(|v| !(v.is_finite() && v.abs() <= MAX_TRACK_MAGNITUDE)) {
                    Some(v) => Err(CaptureError::BadOptions(format!(
                        "{v:e} is beyond ±{MAX_TRACK_MAGNITUDE:e}: not a street scene"
                    ))),
                    None => Ok(()),
                }
            }
        }
    }

    /// The keyed track, if the value moves.
    pub fn keys(&self) -> Option<&Track<N>> {
        match self {
            ValueOrTrack::Keys(track) => Some(track),
            ValueOrTrack::Fixed(_) => None,
        }
    }
}

impl<const N: usize> Serialize for ValueOrTrack<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            ValueOrTrack::Fixed(value) => array_or_scalar::serialize(value, s),
            ValueOrTrack::Keys(track) => track.serialize(s),
        }
    }
}

impl<'de, const N: usize> Deserialize<'de> for ValueOrTrack<N> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error;
        let value = serde_json::Value::deserialize(d)?;
        let is_keys =
            value.as_array().is_some_and(|items| items.first().is_some_and(|item| item.is_object()));
        if is_keys {
            let track: Track<N> = serde_json::from_value(value).map_err(D::Error::custom)?;
            return Ok(ValueOrTrack::Keys(track));
        }
        array_or_scalar::to_array(value)
            .map(ValueOrTrack::Fixed)
            .map_err(|e: D::Error| D::Error::custom(format!("a value or a list of track keys: {e}")))
    }
}

/// Reads `[a, b, c]` or, for one-dimensional tracks, a bare number.
mod array_or_scalar {
    use serde::{Deserialize, Deserializer, Serializer};

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Either {
        One(f64),
        Many(Vec<f64>),
    }

    pub(crate) fn to_array<const N: usize, E: serde::de::Error>(
        value: serde_json::Value,
    ) -> Result<[f64; N], E> {
        let either: Either = serde_json::from_value(value).map_err(E::custom)?;
        let values = match either {
            Either::One(v) => vec![v],
            Either::Many(values) => values,
        };
        values.try_into().map_err(|v: Vec<f64>| E::custom(format!("expected {N} numbers, found {}", v.len())))
    }

    pub(crate) fn serialize<const N: usize, S: Serializer>(
        value: &[f64; N],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        if N == 1 { s.serialize_f64(value[0]) } else { serde::Serialize::serialize(&value[..], s) }
    }

    pub(crate) fn deserialize<'de, const N: usize, D: Deserializer<'de>>(d: D) -> Result<[f64; N], D::Error> {
        to_array(serde_json::Value::deserialize(d)?)
    }
}

mod opt_array_or_scalar {
    use serde::{Deserialize, Deserializer, Serializer};

    pub(crate) fn serialize<const N: usize, S: Serializer>(
        value: &Option<[f64; N]>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        match value {
            Some(value) => super::array_or_scalar::serialize(value, s),
            None => s.serialize_none(),
        }
    }

    pub(crate) fn deserialize<'de, const N: usize, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[f64; N]>, D::Error> {
        match Option::<serde_json::Value>::deserialize(d)? {
            None => Ok(None),
            Some(value) => super::array_or_scalar::to_array(value).map(Some),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_matches_hand_computed_values() {
        // Segment 0→1 over 2 s, slopes 1 and -1 per second.
        let track =
            Track::new(vec![Key::smooth(0.0, [0.0], [1.0]), Key::smooth(2.0, [1.0], [-1.0])]).unwrap();
        assert_eq!(track.eval(0.0), [0.0]);
        assert_eq!(track.eval(2.0), [1.0]);
        // s = 0.5: h00 = 0.5, h10 = 0.125, h01 = 0.5, h11 = -0.125;
        // 0 + 0.125*2*1 + 0.5*1 + (-0.125)*2*(-1) = 1.0
        assert!((track.eval(1.0)[0] - 1.0).abs() < 1e-12);
        // s = 0.25: h10 = 0.140625, h01 = 0.15625, h11 = -0.046875;
        // 0.140625*2 + 0.15625 + 0.046875*2 = 0.53125
        assert!((track.eval(0.5)[0] - 0.53125).abs() < 1e-12);
        // Clamped outside the keys.
        assert_eq!(track.eval(-1.0), [0.0]);
        assert_eq!(track.eval(5.0), [1.0]);
    }

    #[test]
    fn linear_keys_interpolate_linearly_and_braking_decelerates_uniformly() {
        let track =
            Track::new(vec![Key::linear(1.0, [2.0, 4.0, 0.0]), Key::linear(3.0, [4.0, 0.0, 0.0])]).unwrap();
        assert_eq!(track.eval(2.0), [3.0, 2.0, 0.0]);
        // 8 m/s to a stop in 0.7 s over 2.8 m: constant deceleration, so the
        // position is 8t - (8/1.4) t².
        let brake = Track::new(vec![Key::smooth(0.0, [0.0], [8.0]), Key::smooth(0.7, [2.8], [0.0])]).unwrap();
        for t in [0.1, 0.35, 0.6] {
            assert!((brake.eval(t)[0] - (8.0 * t - 8.0 / 1.4 * t * t)).abs() < 1e-9);
        }
    }

    #[test]
    fn stiff_tracks_stay_finite_and_within_the_hermite_bound() {
        // Keys 1 ms apart with the largest slopes allowed, alternating in
        // sign, late in a long scenario (t near 1e5 s, where t - t0 loses
        // digits): every value is finite, keys are hit, and no value leaves
        // the bound |p| <= max|p_k| + (4/27)·dt·(|m0| + |m1|) that the basis
        // functions give (|h10|, |h11| <= 4/27; h00 + h01 = 1, both in [0, 1]).
        let dt = 1e-3;
        let start = 1e5;
        let slope = MAX_TRACK_MAGNITUDE;
        let keys: Vec<Key<1>> = (0..50)
            .map(|i| {
                let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
                Key::smooth(start + f64::from(i) * dt, [sign * 3.0], [sign * slope])
            })
            .collect();
        let track = Track::new(keys.clone()).unwrap();
        let bound = 3.0 + 4.0 / 27.0 * dt * 2.0 * slope;
        for step in 0..=49_000 {
            let t = start + f64::from(step) * 1e-6;
            let [value] = track.eval(t);
            assert!(value.is_finite(), "t = {t}: {value}");
            assert!(value.abs() <= bound * (1.0 + 1e-9), "t = {t}: {value} beyond {bound}");
        }
        for key in &keys {
            assert_eq!(track.eval(key.t), key.value, "key at {} missed", key.t);
        }
        // Slopes one step beyond the street-scale limit are refused, not evaluated.
        let too_stiff =
            Track::new(vec![Key::smooth(0.0, [0.0], [slope * 1.01]), Key::smooth(dt, [0.0], [0.0])]);
        assert!(too_stiff.is_err());
    }

    #[test]
    fn parses_scalar_and_vector_keys_and_rejects_unsorted() {
        let yaw: Track<1> =
            serde_json::from_str(r#"[{"t":0,"value":90,"in_slope":0,"out_slope":0},{"t":1,"value":0}]"#)
                .unwrap();
        assert_eq!(yaw.eval(0.5), [45.0]);
        let pos: Track<3> = serde_json::from_str(r#"[{"t":0,"value":[1,2,3]}]"#).unwrap();
        assert_eq!(pos.eval(9.0), [1.0, 2.0, 3.0]);
        let bad = Track::new(vec![Key::linear(1.0, [0.0]), Key::linear(1.0, [1.0])]);
        assert!(bad.is_err());
    }
}
