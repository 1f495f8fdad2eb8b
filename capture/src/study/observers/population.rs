//! Who the observers are: drawn from a declared population, not a grid of
//! guesses.
//!
//! A population ([`ufcsr::format::ObserverPopulation`]) says where people stand (the
//! rig's pedestrian, uniformly along a kerb segment or over a rectangle)
//! and how tall they are (a mixture of groups, each normal in stature with
//! a named source, eye height = stature − an offset). [`sample_observers`]
//! draws observers from it independently (seeded SplitMix64, so a seed
//! gives the same observers on every machine): independent draws are what
//! make the Student-t interval of their mean a valid interval of the
//! population mean. The old deterministic grid stays as an explicit
//! [`ufcsr::format::ObserverSampling::Grid`], for which no interval is claimed.

use ufcsr::{
    format::ObserverPlace, format::ObserverPopulation, format::ObserverSampling, format::StatureGroup,
};

use crate::error::{CaptureError, Result};
use ufcsr::SplitMix64;

/// The most observers one study captures (each is a full capture).
pub const MAX_OBSERVERS: u32 = 400;

/// Eye heights the rig accepts, metres above the ground point.
const EYE_HEIGHT_RANGE_M: [f64; 2] = [0.1, 3.0];

/// One observer to capture.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledObserver {
    /// Ground point, world metres.
    pub position: [f64; 3],
    /// The group drawn (`None` on a grid).
    pub group: Option<String>,
    /// The stature drawn (`None` on a grid).
    pub stature_m: Option<f64>,
    pub eye_height_m: f64,
}

fn bad<T>(text: String) -> Result<T> {
    Err(CaptureError::BadOptions(text))
}

/// Refuses a population that cannot be drawn from or that puts an eye
/// outside 0.1–3 m, naming the field.
pub fn check_population(population: &ObserverPopulation) -> Result<()> {
    let coordinates: Vec<f64> = match population.place {
        ObserverPlace::Rig => Vec::new(),
        ObserverPlace::Kerb { from, to } => [from, to].concat(),
        ObserverPlace::Area { corner, opposite } => [corner, opposite].concat(),
    };
    if coordinates.iter().any(|v| !v.is_finite() || v.abs() > 1e6) {
        return bad(format!(
            "the population's place (--kerb / --area) must have finite ends within ±1e6 m, not {:?}",
            population.place
        ));
    }
    let truncate = population.truncate_sd;
    if !(truncate.is_finite() && (0.5..=10.0).contains(&truncate)) {
        return bad(format!("the population's truncate_sd must be between 0.5 and 10, not {truncate}"));
    }
    if population.groups.is_empty() {
        return bad("the population needs at least one group (--group)".into());
    }
    population.groups.iter().try_for_each(|group| check_group(group, truncate))
}

fn check_group(group: &StatureGroup, truncate: f64) -> Result<()> {
    let StatureGroup { name, weight, stature_mean_m: mean, stature_sd_m: sd, eye_offset_m: offset, .. } =
        group;
    let finite = [weight, mean, sd, offset].iter().all(|v| v.is_finite());
    if !finite || *weight <= 0.0 || *sd < 0.0 || *sd > 0.5 || !(0.0..0.5).contains(offset) {
        return bad(format!(
            "population group {name:?} (--group): weight must be positive, stature_sd_m within 0–0.5 m and \
             eye_offset_m within 0–0.5 m, not weight {weight}, SD {sd}, offset {offset}"
        ));
    }
    let [lowest, highest] = [mean - truncate * sd - offset, mean + truncate * sd - offset];
    if lowest < EYE_HEIGHT_RANGE_M[0] || highest > EYE_HEIGHT_RANGE_M[1] {
        return bad(format!(
            "population group {name:?} (--group): its eye heights reach {lowest:.3}–{highest:.3} m (stature \
             {mean} ± {truncate} × {sd} m − {offset} m), outside {}–{} m",
            EYE_HEIGHT_RANGE_M[0], EYE_HEIGHT_RANGE_M[1]
        ));
    }
    Ok(())
}

/// Refuses a sampling that asks for no observers, more than
/// [`MAX_OBSERVERS`], or grid positions without a place to put them.
pub(crate) fn check_sampling(sampling: &ObserverSampling, place: &ObserverPlace) -> Result<()> {
    let (count, what) = match sampling {
        ObserverSampling::Random { observers, .. } => {
            (u64::from(*observers), format!("--observers {observers}"))
        }
        ObserverSampling::Grid { positions, heights, .. } => (
            u64::from(*positions) * u64::from(*heights),
            format!("--positions × --heights = {positions} × {heights}"),
        ),
    };
    if count == 0 || count > u64::from(MAX_OBSERVERS) {
        return bad(format!("{what}: the study needs between 1 and {MAX_OBSERVERS} observers"));
    }
    if let ObserverSampling::Grid { positions, eye_heights_m: [low, high], .. } = *sampling {
        if positions != 1 && *place == ObserverPlace::Rig {
            return bad("--positions above 1 needs a --kerb segment (or --area) to place them on".into());
        }
        let [min, max] = EYE_HEIGHT_RANGE_M;
        if !(low.is_finite() && high.is_finite() && low >= min && low <= high && high <= max) {
            return bad(format!(
                "--eye-heights must be LOW:HIGH with {min} ≤ LOW ≤ HIGH ≤ {max} m, not {low}:{high}"
            ));
        }
    }
    Ok(())
}

/// The observers to capture: independent draws from `population`, or the
/// grid. `anchor` is the rig's pedestrian (its ground height is kept).
pub fn sample_observers(
    population: &ObserverPopulation,
    sampling: &ObserverSampling,
    anchor: [f64; 3],
) -> Result<Vec<SampledObserver>> {
    check_population(population)?;
    check_sampling(sampling, &population.place)?;
    Ok(match *sampling {
        ObserverSampling::Random { observers, seed } => {
            let mut random = SplitMix64(seed);
            (0..observers).map(|_| draw(population, anchor, &mut random)).collect()
        }
        ObserverSampling::Grid { positions, heights, eye_heights_m: [low, high] } => {
            let mut grid = Vec::new();
            for p in 0..positions {
                let u = midpoint(0.0, 1.0, p, positions);
                let position = place_at(&population.place, anchor, [u, 0.5]);
                for h in 0..heights {
                    let eye_height_m = midpoint(low, high, h, heights);
                    grid.push(SampledObserver { position, group: None, stature_m: None, eye_height_m });
                }
            }
            grid
        }
    })
}

/// Where cell `i` of `n` on `[from, to]` has its middle.
fn midpoint(from: f64, to: f64, i: u32, n: u32) -> f64 {
    from + (to - from) * (f64::from(i) + 0.5) / f64::from(n)
}

/// The ground point at unit coordinates `u` of the place (the second is
/// used by an area only).
fn place_at(place: &ObserverPlace, anchor: [f64; 3], u: [f64; 2]) -> [f64; 3] {
    match *place {
        ObserverPlace::Rig => anchor,
        ObserverPlace::Kerb { from, to } => {
            [from[0] + (to[0] - from[0]) * u[0], from[1] + (to[1] - from[1]) * u[0], anchor[2]]
        }
        ObserverPlace::Area { corner, opposite } => [
            corner[0] + (opposite[0] - corner[0]) * u[0],
            corner[1] + (opposite[1] - corner[1]) * u[1],
            anchor[2],
        ],
    }
}

/// One independent observer: place, group by weight, truncated-normal stature.
fn draw(population: &ObserverPopulation, anchor: [f64; 3], random: &mut SplitMix64) -> SampledObserver {
    let position = place_at(&population.place, anchor, [random.uniform(), random.uniform()]);
    let total: f64 = population.groups.iter().map(|g| g.weight).sum();
    let mut pick = random.uniform() * total;
    let group = population
        .groups
        .iter()
        .find(|g| {
            pick -= g.weight;
            pick < 0.0
        })
        .unwrap_or(&population.groups[population.groups.len() - 1]);
    // Rejection outside ± truncate_sd (≥ 0.5 SD: at least 38 % of draws are kept).
    let z = loop {
        let z = random.normal();
        if z.abs() <= population.truncate_sd {
            break z;
        }
    };
    let stature_m = group.stature_mean_m + group.stature_sd_m * z;
    SampledObserver {
        position,
        group: Some(group.name.clone()),
        stature_m: Some(stature_m),
        eye_height_m: stature_m - group.eye_offset_m,
    }
}

/// The standard normal CDF (Abramowitz & Stegun 7.1.26 for erf, |error| < 1.5e-7).
pub fn normal_cdf(z: f64) -> f64 {
    let x = z.abs() / std::f64::consts::SQRT_2;
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736 + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let erf = 1.0 - poly * (-x * x).exp();
    if z >= 0.0 { 0.5 * (1.0 + erf) } else { 0.5 * (1.0 - erf) }
}

/// The population's eye-height CDF at `h` metres (the truncated mixture).
fn eye_height_cdf(population: &ObserverPopulation, h: f64) -> f64 {
    let total: f64 = population.groups.iter().map(|g| g.weight).sum();
    let t = population.truncate_sd;
    let kept = normal_cdf(t) - normal_cdf(-t);
    population
        .groups
        .iter()
        .map(|g| {
            let eye = g.stature_mean_m - g.eye_offset_m;
            let within = if g.stature_sd_m > 0.0 {
                let z = ((h - eye) / g.stature_sd_m).clamp(-t, t);
                (normal_cdf(z) - normal_cdf(-t)) / kept
            } else if h >= eye {
                1.0
            } else {
                0.0
            };
            g.weight / total * within
        })
        .sum()
}

/// The eye height below which a share `q` (0–1) of the population's eyes
/// lie (bisection on the mixture's CDF, to 0.1 mm): e.g. the documented
/// default range of the grid, the 5th to 95th percentile.
pub fn eye_height_quantile(population: &ObserverPopulation, q: f64) -> f64 {
    let (mut low, mut high) = (EYE_HEIGHT_RANGE_M[0] - 1.0, EYE_HEIGHT_RANGE_M[1] + 1.0);
    while high - low > 1e-4 {
        let middle = 0.5 * (low + high);
        if eye_height_cdf(population, middle) < q {
            low = middle;
        } else {
            high = middle;
        }
    }
    0.5 * (low + high)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kerb() -> ObserverPopulation {
        ObserverPopulation::us_adults(ObserverPlace::Kerb { from: [0.0, 0.0], to: [4.0, -2.0] })
    }

    #[test]
    fn random_observers_follow_the_declared_mixture_and_a_seed_repeats_them() {
        let sampling = ObserverSampling::Random { observers: 400, seed: 11 };
        let drawn = sample_observers(&kerb(), &sampling, [9.0, 9.0, 0.25]).unwrap();
        assert_eq!(drawn, sample_observers(&kerb(), &sampling, [9.0, 9.0, 0.25]).unwrap());
        let other =
            sample_observers(&kerb(), &ObserverSampling::Random { observers: 400, seed: 12 }, [0.0; 3]);
        assert_ne!(drawn[0].eye_height_m, other.unwrap()[0].eye_height_m);
        // On the segment, at the rig's ground height; eye = stature − 0.11 m.
        for o in &drawn {
            let u = o.position[0] / 4.0;
            assert!(
                (0.0..=1.0).contains(&u) && (o.position[1] + 2.0 * u).abs() < 1e-12 && o.position[2] == 0.25
            );
            assert!((o.stature_m.unwrap() - o.eye_height_m - 0.11).abs() < 1e-12);
        }
        // Women's statures: mean 1.613 m, SD 0.071 (400 draws, of which about half are women: ±4 SE).
        let women: Vec<f64> = drawn
            .iter()
            .filter(|o| o.group.as_deref() == Some("women"))
            .map(|o| o.stature_m.unwrap())
            .collect();
        let n = women.len() as f64;
        assert!((n / 400.0 - 0.5).abs() < 4.0 * (0.25_f64 / 400.0).sqrt(), "{n} women of 400");
        let mean = women.iter().sum::<f64>() / n;
        assert!((mean - 1.613).abs() < 4.0 * 0.071 / n.sqrt(), "{mean}");
        let sd = (women.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        assert!((sd / 0.071 - 1.0).abs() < 0.2, "{sd}");
    }

    #[test]
    fn the_grid_puts_each_observer_at_the_middle_of_its_cell() {
        let grid = ObserverSampling::Grid { positions: 2, heights: 4, eye_heights_m: [1.5, 1.9] };
        let drawn = sample_observers(&kerb(), &grid, [9.0, 9.0, 0.25]).unwrap();
        assert_eq!(drawn.len(), 8);
        assert_eq!(drawn[0].position, [1.0, -0.5, 0.25]);
        assert_eq!(drawn[4].position, [3.0, -1.5, 0.25]);
        for (o, want) in drawn[..4].iter().zip([1.55, 1.65, 1.75, 1.85]) {
            assert!((o.eye_height_m - want).abs() < 1e-12 && o.group.is_none());
        }
        let rig = ObserverPopulation::us_adults(ObserverPlace::Rig);
        let one = ObserverSampling::Grid { positions: 1, heights: 1, eye_heights_m: [1.5, 1.9] };
        assert_eq!(sample_observers(&rig, &one, [9.0, 9.0, 0.25]).unwrap()[0].position, [9.0, 9.0, 0.25]);
    }

    #[test]
    fn the_default_adults_eye_heights_have_the_mixtures_percentiles() {
        // Equal mixture of N(1.503, 0.071) and N(1.643, 0.076): the median lies between the two means,
        // the 5th percentile near the women's (1.503 − 1.645 × 0.071 = 1.386 m would be the women's alone).
        let rig = ObserverPopulation::us_adults(ObserverPlace::Rig);
        let median = eye_height_quantile(&rig, 0.5);
        assert!((median - 1.573).abs() < 0.01, "{median}");
        let (p5, p95) = (eye_height_quantile(&rig, 0.05), eye_height_quantile(&rig, 0.95));
        assert!((1.40..1.43).contains(&p5) && (1.72..1.75).contains(&p95), "{p5} {p95}");
        assert!((normal_cdf(1.959_964) - 0.975).abs() < 1e-6 && (normal_cdf(0.0) - 0.5).abs() < 1e-9);
    }

    #[test]
    fn bad_populations_and_samplings_are_refused_with_the_field_named() {
        let mut tall = kerb();
        tall.groups[0].stature_mean_m = 3.5;
        let mut no_weight = kerb();
        no_weight.groups[1].weight = 0.0;
        let far = ObserverPopulation::us_adults(ObserverPlace::Kerb { from: [0.0, 1e300], to: [1.0, 1.0] });
        let truncated = ObserverPopulation { truncate_sd: f64::NAN, ..kerb() };
        let empty = ObserverPopulation { groups: Vec::new(), ..kerb() };
        let random = ObserverSampling::Random { observers: 4, seed: 1 };
        for (population, named) in [
            (tall, "women"),
            (no_weight, "men"),
            (far, "--kerb"),
            (truncated, "truncate_sd"),
            (empty, "--group"),
        ] {
            let message = sample_observers(&population, &random, [0.0; 3]).unwrap_err().to_string();
            assert!(message.contains(named), "{message} should name {named}");
        }
        let rig = ObserverPopulation::us_adults(ObserverPlace::Rig);
        let cases = [
            (ObserverSampling::Random { observers: 0, seed: 1 }, "--observers"),
            (ObserverSampling::Random { observers: 401, seed: 1 }, "--observers"),
            (
                ObserverSampling::Grid { positions: 30, heights: 30, eye_heights_m: [1.5, 1.9] },
                "--positions × --heights",
            ),
            (ObserverSampling::Grid { positions: 3, heights: 1, eye_heights_m: [1.5, 1.9] }, "--kerb"),
            (ObserverSampling::Grid { positions: 1, heights: 2, eye_heights_m: [1.9, 1.5] }, "--eye-heights"),
        ];
        for (sampling, named) in cases {
            let message = sample_observers(&rig, &sampling, [0.0; 3]).unwrap_err().to_string();
            assert!(message.contains(named), "{message} should name {named}");
        }
    }
}
