//! Reproducible random fields of joint properties (heterogeneous strength).
//!
//! A [`Distribution`] and a seed give every joint `k` its value from a counter-based
//! generator: the uniform numbers of joint `k` are a hash (SplitMix64) of `(seed, k, draw)`,
//! so the field is the same bit for bit whatever the order in which joints are visited, the
//! number of threads, or how many joints there are; different seeds give independent fields.
//!
//! - **Weibull** (modulus `m`, scale `lambda`): `x = lambda (-ln(1 - u))^(1/m)`, CDF
//!   `1 - exp(-(x/lambda)^m)`, mean `lambda Gamma(1 + 1/m)`.
//! - **Normal** (mean `mu`, coefficient of variation `cov`), truncated to positive values:
//!   Box-Muller draws, a draw `<= 0` is replaced by the next draw of the same joint, so the
//!   values follow the normal law conditioned on `x > 0`.
//! - **Lognormal** (mean `mu`, coefficient of variation `cov` of the values themselves):
//!   `x = exp(m + s z)` with `s^2 = ln(1 + cov^2)`, `m = ln(mu) - s^2/2`, `z` standard normal.
//!
//! A [`Heterogeneity`] draws some of a joint material's fields (strengths, fracture energies)
//! per joint, each field from its own stream ([`stream_seed`]), so that drawing one more field
//! leaves the values of the others unchanged.

use serde::{Deserialize, Serialize};

use crate::error::FractureError;
use crate::material::JointMaterialInput;

/// A distribution of a positive joint property (strength [Pa] or fracture energy [J/m^2]).
/// In JSON: `{"weibull": {"modulus": 6, "scale": 5e6}}`, `{"normal": {"mean": .., "cov": ..}}`
/// or `{"lognormal": {"mean": .., "cov": ..}}`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Distribution {
    /// Weibull law.
    Weibull {
        /// Weibull modulus `m` > 0 (larger: narrower).
        modulus: f64,
        /// Scale `lambda` > 0, in the property's unit.
        scale: f64,
    },
    /// Normal law truncated to x > 0.
    Normal {
        /// Mean of the untruncated law, > 0.
        mean: f64,
        /// Coefficient of variation (deviation over mean) of the untruncated law, > 0.
        cov: f64,
    },
    /// Lognormal law.
    Lognormal {
        /// Mean of the values, > 0.
        mean: f64,
        /// Coefficient of variation of the values, > 0.
        cov: f64,
    },
}

impl Distribution {
    /// Checks the parameters: each finite and positive. The error names the parameter.
    pub fn validate(&self) -> Result<(), FractureError> {
        let params: [(&str, f64); 2] = match *self {
            Distribution::Weibull { modulus, scale } => [("modulus", modulus), ("scale", scale)],
            Distribution::Normal { mean, cov } | Distribution::Lognormal { mean, cov } => {
                [("mean", mean), ("cov", cov)]
            }
        };
        for (name, v) in params {
            if !(v.is_finite() && v > 0.0) {
                return Err(FractureError::InvalidDistribution {
                    field: name,
                    value: v,
                });
            }
        }
        Ok(())
    }

    /// The value of joint `index` in the field of `seed` (parameters assumed valid).
    pub fn sample(&self, seed: u64, index: u64) -> f64 {
        let mut draw = 0u64;
        let mut uniform = || {
            draw += 1;
            unit_open(hash3(seed, index, draw))
        };
        match *self {
            Distribution::Weibull { modulus, scale } => {
                scale * (-(1.0 - uniform()).ln()).powf(1.0 / modulus)
            }
            Distribution::Normal { mean, cov } => loop {
                let x = mean * (1.0 + cov * standard_normal(&mut uniform));
                if x > 0.0 {
                    break x;
                }
            },
            Distribution::Lognormal { mean, cov } => {
                let s2 = (1.0 + cov * cov).ln();
                (mean.ln() - 0.5 * s2 + s2.sqrt() * standard_normal(&mut uniform)).exp()
            }
        }
    }

    /// The cumulative distribution function at `x` (of the truncated law for `Normal`).
    pub fn cdf(&self, x: f64) -> f64 {
        if x <= 0.0 {
            return 0.0;
        }
        match *self {
            Distribution::Weibull { modulus, scale } => 1.0 - (-(x / scale).powf(modulus)).exp(),
            Distribution::Normal { mean, cov } => {
                let sd = mean * cov;
                let below_zero = normal_cdf(-mean / sd);
                (normal_cdf((x - mean) / sd) - below_zero) / (1.0 - below_zero)
            }
            Distribution::Lognormal { mean, cov } => {
                let s2 = (1.0 + cov * cov).ln();
                normal_cdf((x.ln() - (mean.ln() - 0.5 * s2)) / s2.sqrt())
            }
        }
    }
}

/// The seed of stream `stream` of the field of `seed`: the fields of one seed drawn for
/// different properties are independent (the generator's draw counter 0, never used by
/// [`Distribution::sample`], keeps the streams apart from the values).
pub fn stream_seed(seed: u64, stream: u64) -> u64 {
    hash3(seed, stream, 0)
}

/// The fields of a joint material drawn per joint (fields left `None` keep the material's
/// value). In JSON (`deny_unknown_fields`): `{"seed": 7, "tensile_strength": {"weibull":
/// {...}}, "cohesion": ..., "fracture_energy_i": ..., "fracture_energy_ii": ...}`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Heterogeneity {
    /// Seed of the fields (the same seed, the same values on any number of threads).
    pub seed: u64,
    /// Tensile strength `ft` [Pa].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tensile_strength: Option<Distribution>,
    /// Cohesion `c` [Pa].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cohesion: Option<Distribution>,
    /// Mode I fracture energy `G_I` [J/m^2].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fracture_energy_i: Option<Distribution>,
    /// Mode II fracture energy `G_II` [J/m^2].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fracture_energy_ii: Option<Distribution>,
}

impl Heterogeneity {
    /// The drawn fields with their names as written in the input, in stream order (stream
    /// `k` is field `k` of this list, given or not).
    pub fn fields(&self) -> [(&'static str, Option<Distribution>); 4] {
        [
            ("tensile_strength", self.tensile_strength),
            ("cohesion", self.cohesion),
            ("fracture_energy_i", self.fracture_energy_i),
            ("fracture_energy_ii", self.fracture_energy_ii),
        ]
    }

    /// True when no field is drawn.
    pub fn is_empty(&self) -> bool {
        self.fields().iter().all(|(_, d)| d.is_none())
    }

    /// Checks every distribution; the error names the field (`cohesion.weibull.scale`).
    pub fn validate(&self) -> Result<(), FractureError> {
        for (name, d) in self.fields() {
            if let Some(d) = d {
                d.validate().map_err(|e| match e {
                    FractureError::InvalidDistribution { field, value } => {
                        FractureError::InvalidHeterogeneity {
                            field: format!("{name}.{}.{field}", d.law()),
                            value,
                        }
                    }
                    other => other,
                })?;
            }
        }
        Ok(())
    }

    /// The material of joint `joint` (its global index): `base` with the drawn fields replaced
    /// by their values for that joint.
    pub fn draw(&self, base: &JointMaterialInput, joint: u64) -> JointMaterialInput {
        let mut m = *base;
        let targets = [
            &mut m.tensile_strength,
            &mut m.cohesion,
            &mut m.fracture_energy_i,
            &mut m.fracture_energy_ii,
        ];
        for (k, ((_, d), v)) in self.fields().into_iter().zip(targets).enumerate() {
            if let Some(d) = d {
                *v = d.sample(stream_seed(self.seed, k as u64), joint);
            }
        }
        m
    }
}

impl Distribution {
    /// The law's name as written in the input.
    pub fn law(&self) -> &'static str {
        match self {
            Distribution::Weibull { .. } => "weibull",
            Distribution::Normal { .. } => "normal",
            Distribution::Lognormal { .. } => "lognormal",
        }
    }
}

/// Fills `out[k]` with the value of joint `first + k` (the same values in any chunking).
pub fn fill(dist: &Distribution, seed: u64, first: u64, out: &mut [f64]) {
    for (k, v) in out.iter_mut().enumerate() {
        *v = dist.sample(seed, first + k as u64);
    }
}

/// A standard normal number from two uniforms (Box-Muller, cosine branch).
fn standard_normal(uniform: &mut impl FnMut() -> f64) -> f64 {
    let (u1, u2) = (uniform(), uniform());
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// SplitMix64's finaliser: a bijective mix of 64 bits.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The counter-based generator: 64 random bits for (seed, joint, draw).
fn hash3(seed: u64, index: u64, draw: u64) -> u64 {
    const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;
    mix(mix(mix(seed.wrapping_add(GOLDEN)) ^ index.wrapping_mul(GOLDEN)) ^ draw)
}

/// A uniform number in the open interval (0, 1) from the top 53 bits.
fn unit_open(bits: u64) -> f64 {
    ((bits >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// The standard normal CDF, `Phi(x) = erfc(-x/sqrt 2)/2`.
fn normal_cdf(x: f64) -> f64 {
    0.5 * erfc(-x / std::f64::consts::SQRT_2)
}

/// The complementary error function (Numerical Recipes' Chebyshev fit `erfcc`, relative
/// error below 1.2e-7 everywhere).
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

/// Gamma function by the Lanczos approximation (g = 7, 9 terms; about 1e-15 relative):
/// `scale * gamma(1 + 1/m)` is the mean of a Weibull law of modulus `m`.
pub fn gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let t = x + 7.5;
    let s: f64 = C[0] + (1..9).map(|i| C[i] / (x + i as f64)).sum::<f64>();
    (2.0 * std::f64::consts::PI).sqrt() * t.powf(x + 0.5) * (-t).exp() * s
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: usize = 100_000;

    /// Mean, standard deviation and the Kolmogorov-Smirnov statistic of `N` draws.
    fn statistics(d: &Distribution, seed: u64) -> (f64, f64, f64) {
        let mut x = vec![0.0; N];
        fill(d, seed, 0, &mut x);
        let mean = x.iter().sum::<f64>() / N as f64;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (N - 1) as f64;
        x.sort_by(f64::total_cmp);
        let ks = x
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                let f = d.cdf(v);
                (f - i as f64 / N as f64).max((i + 1) as f64 / N as f64 - f)
            })
            .fold(0.0, f64::max);
        (mean, var.sqrt(), ks)
    }

    /// The KS statistic of a correct sampler stays below 1.63/sqrt(N) with probability 0.99;
    /// the mean within 5 standard errors (sd/sqrt N), the deviation within 3 %.
    /// Asserts the draws' mean, deviation and KS distance and records them as part `part` of
    /// validation row 54.
    fn assert_matches(part: u32, d: Distribution, mean: f64, sd: f64) {
        let (m, s, ks) = statistics(&d, 42);
        let se = sd / (N as f64).sqrt();
        assert!(
            (m - mean).abs() < 5.0 * se,
            "{d:?}: mean {m} against {mean} (se {se})"
        );
        assert!(
            (s / sd - 1.0).abs() < 0.03,
            "{d:?}: deviation {s} against {sd}"
        );
        assert!(ks < 1.63 / (N as f64).sqrt(), "{d:?}: KS statistic {ks}");
        let name = ["Weibull", "lognormal", "truncated normal"][part as usize - 1];
        fdem_figures::record_part(
            54,
            part,
            format!(
                "{name}: mean {:+.1} standard errors, deviation {:+.2} %, KS {:.2} of its bound",
                (m - mean) / se,
                100.0 * (s / sd - 1.0),
                ks * (N as f64).sqrt() / 1.63
            ),
        );
    }

    #[test]
    fn weibull_draws_match_the_law() {
        let (m, lambda) = (6.0, 5e6);
        let mean = lambda * gamma(1.0 + 1.0 / m);
        let sd = lambda * (gamma(1.0 + 2.0 / m) - gamma(1.0 + 1.0 / m).powi(2)).sqrt();
        assert_matches(
            1,
            Distribution::Weibull {
                modulus: m,
                scale: lambda,
            },
            mean,
            sd,
        );
    }

    #[test]
    fn lognormal_draws_match_the_law() {
        assert_matches(
            2,
            Distribution::Lognormal {
                mean: 5e6,
                cov: 0.3,
            },
            5e6,
            1.5e6,
        );
    }

    #[test]
    fn truncated_normal_draws_match_the_law() {
        // cov 0.2: the truncation at 0 (5 deviations below the mean) moves nothing measurable.
        assert_matches(
            3,
            Distribution::Normal {
                mean: 5e6,
                cov: 0.2,
            },
            5e6,
            1e6,
        );
        // cov 0.8: a fifth of the normal law lies below 0; the KS test is against the
        // truncated law, so a sampler that kept or clipped the negative draws fails it.
        let d = Distribution::Normal {
            mean: 1.0,
            cov: 0.8,
        };
        let (_, _, ks) = statistics(&d, 7);
        assert!(ks < 1.63 / (N as f64).sqrt(), "truncated normal KS {ks}");
    }

    #[test]
    fn the_field_depends_on_the_seed_and_the_joint_only() {
        let d = Distribution::Weibull {
            modulus: 3.0,
            scale: 1.0,
        };
        let mut whole = vec![0.0; 1000];
        fill(&d, 9, 0, &mut whole);
        // filled in chunks, in reverse order: the same bits
        let mut chunked = vec![0.0; 1000];
        for (c, chunk) in chunked.chunks_mut(64).enumerate().rev() {
            fill(&d, 9, (c * 64) as u64, chunk);
        }
        assert!(
            whole
                .iter()
                .zip(&chunked)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
        let mut other = vec![0.0; 1000];
        fill(&d, 10, 0, &mut other);
        let same = whole.iter().zip(&other).filter(|(a, b)| a == b).count();
        assert_eq!(same, 0, "another seed gives another field");
    }

    #[test]
    fn a_non_positive_parameter_is_refused_by_name() {
        let bad = [
            (
                Distribution::Weibull {
                    modulus: 0.0,
                    scale: 1.0,
                },
                "modulus",
            ),
            (
                Distribution::Weibull {
                    modulus: 2.0,
                    scale: -1.0,
                },
                "scale",
            ),
            (
                Distribution::Normal {
                    mean: f64::NAN,
                    cov: 0.1,
                },
                "mean",
            ),
            (
                Distribution::Lognormal {
                    mean: 1.0,
                    cov: 0.0,
                },
                "cov",
            ),
        ];
        for (d, name) in bad {
            let e = d.validate().unwrap_err().to_string();
            assert!(e.contains(&format!("`{name}`")), "{d:?}: {e}");
        }
        assert!(
            Distribution::Lognormal {
                mean: 1.0,
                cov: 0.5
            }
            .validate()
            .is_ok()
        );
    }

    #[test]
    fn a_heterogeneity_draws_only_its_fields_each_from_its_own_stream() {
        let base = JointMaterialInput {
            tensile_strength: 5e6,
            cohesion: 10e6,
            friction_angle_deg: 30.0,
            fracture_energy_i: 50.0,
            fracture_energy_ii: 250.0,
            penalty_normal: 3e12,
            penalty_tangential: 3e12,
        };
        let w = Distribution::Weibull {
            modulus: 6.0,
            scale: 5e6,
        };
        let h = Heterogeneity {
            seed: 7,
            tensile_strength: Some(w),
            cohesion: None,
            fracture_energy_i: None,
            fracture_energy_ii: None,
        };
        let both = Heterogeneity {
            cohesion: Some(w),
            ..h
        };
        for j in 0..100u64 {
            let (a, b) = (h.draw(&base, j), both.draw(&base, j));
            // drawing the cohesion too leaves the tensile strengths' bits unchanged
            assert_eq!(a.tensile_strength.to_bits(), b.tensile_strength.to_bits());
            assert_eq!(
                a.tensile_strength.to_bits(),
                w.sample(stream_seed(7, 0), j).to_bits()
            );
            assert_eq!(a.cohesion, 10e6);
            assert_ne!(b.cohesion, b.tensile_strength, "one stream per field");
            assert_eq!(
                (a.fracture_energy_i, a.friction_angle_deg, a.penalty_normal),
                (50.0, 30.0, 3e12)
            );
        }
        let bad = Heterogeneity {
            cohesion: Some(Distribution::Lognormal {
                mean: 1e6,
                cov: -0.1,
            }),
            ..h
        };
        let e = bad.validate().unwrap_err().to_string();
        assert!(e.contains("`cohesion.lognormal.cov`"), "{e}");
        assert!(h.validate().is_ok() && !h.is_empty());
    }

    #[test]
    fn erfc_matches_known_values() {
        // erfc(0) = 1, erfc(1) = 0.157299207050285, erfc(-1) = 1.842700792949715,
        // erfc(2) = 0.004677734981047266
        for (x, v) in [
            (0.0, 1.0),
            (1.0, 0.157_299_207_050_285),
            (-1.0, 1.842_700_792_949_715),
        ] {
            assert!((erfc(x) - v).abs() < 2e-7, "erfc({x}) = {}", erfc(x));
        }
        assert!((erfc(2.0) / 0.004_677_734_981_047_266 - 1.0).abs() < 1.2e-7 * 4.0);
    }
}
