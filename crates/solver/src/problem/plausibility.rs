//! Materials outside the range this field models (rocks, concretes, ceramics, glasses,
//! metals), judged by ratios that do not depend on the system of units: a modulus typed in
//! GPa as Pa, a density in g/cm^3, a strength in MPa. Such a scene is valid and runs, but gives answers that are wrong by a factor of a
//! thousand or more; the [`units`] indicator names each value, its likely slip and the fix.

use serde_json::json;

use crate::input::scene::Scene;
use crate::problem::indicator::{Good, Indicator, number};

/// A ratio's plausible range, and the unit slips to try on a value outside it.
struct Range {
    what: &'static str,
    unit: &'static str,
    low: f64,
    high: f64,
    /// `(factor on the ratio, "what was typed in which unit")`: the ratio times `factor`
    /// lies in the range when that slip happened.
    slips: &'static [(f64, &'static str)],
}

/// The bar wave speed `sqrt(E / rho)`: about 50 m/s (soft soils, rubbers) to 18 km/s
/// (diamond); E typed in GPa as Pa gives 3e-5 of the speed, rho in g/cm^3 as kg/m^3 32 times it.
const WAVE_SPEED: Range = Range {
    what: "bar wave speed sqrt(young / density)",
    unit: "m/s",
    low: 30.0,
    high: 2e4,
    slips: &[
        (3.1623e4, "young in GPa"),
        (1e3, "young in MPa"),
        (3.1623e-2, "density in g/cm^3"),
    ],
};
/// A strength over the largest Young's modulus: 1e-5 (weak rock joints) to 0.05 (glass
/// fibres); a strength typed in MPa as Pa gives 1e-6 of it.
const STRENGTH: Range = Range {
    what: "strength / Young's modulus",
    unit: "",
    low: 1e-7,
    high: 0.1,
    slips: &[(1e6, "the strength in MPa"), (1e-9, "young in GPa")],
};
/// The characteristic length `E G_I / ft^2`: micrometres (glass, ceramics) to metres (rock
/// masses, concrete dams).
const CHARACTERISTIC_LENGTH: Range = Range {
    what: "characteristic length young fracture_energy / strength^2",
    unit: "m",
    low: 1e-7,
    high: 1e3,
    slips: &[
        (1e3, "the fracture energy in N/mm (kJ/m^2)"),
        (1e-3, "the fracture energy in J/m^2 as kJ/m^2"),
    ],
};

/// One ratio outside its range: its path, the value and the sentence that explains it.
fn out_of_range(path: String, value: f64, r: &Range) -> Option<(String, f64, String)> {
    if !value.is_finite() || (r.low..=r.high).contains(&value) {
        return None;
    }
    let slip = r
        .slips
        .iter()
        .find(|(f, _)| (r.low..=r.high).contains(&(value * f)))
        .map(|(_, what)| format!("; {what}?"))
        .unwrap_or_default();
    let text = format!(
        "{path}: {} {} {}, outside {} to {} of the field's materials{slip}",
        r.what,
        number(value),
        r.unit,
        number(r.low),
        number(r.high),
    );
    Some((path, value, text))
}

/// The scene's materials whose wave speed, strength over modulus or characteristic length
/// lies outside the field's range: the value is their count (none passes). Ratios, not
/// values: a scene in a consistent system of other units (N, mm, tonne) passes.
pub fn units(scene: &Scene) -> Indicator {
    let mut found = Vec::new();
    let mut young_max: f64 = 0.0;
    for (b, body) in scene.bodies.iter().enumerate() {
        for (key, m) in &body.materials {
            let at = format!("bodies[{b}].materials.{key}");
            let young = m.heterogeneity.as_ref().map_or(m.young, |h| h.young(0));
            young_max = young_max.max(young);
            let c = (young / m.density).sqrt();
            found.extend(out_of_range(at, c, &WAVE_SPEED));
        }
    }
    if let Some(section) = &scene.fracture {
        for m in section.material_list() {
            let (at, row) = (m.path(), m.spec.row(0));
            let (ft, c) = (row.tensile_strength, row.cohesion);
            let values = [
                ("tensile_strength", ft / young_max, &STRENGTH),
                ("cohesion", c / young_max, &STRENGTH),
                (
                    "fracture_energy_i",
                    young_max * row.fracture_energy_i / (ft * ft),
                    &CHARACTERISTIC_LENGTH,
                ),
                (
                    "fracture_energy_ii",
                    young_max * row.fracture_energy_ii / (c * c),
                    &CHARACTERISTIC_LENGTH,
                ),
            ];
            for (field, v, r) in values {
                found.extend(out_of_range(format!("{at}.{field}"), v, r));
            }
        }
    }
    let mut ind = Indicator {
        name: "units".into(),
        subject: "scene".into(),
        measure: "materials outside the range of rocks, concretes, ceramics and metals".into(),
        value: found.len() as f64,
        threshold: 0.0,
        good: Good::AtMost,
        meaning: "a wave speed, strength or characteristic length far outside the field's \
                  materials is most often a unit slip (GPa typed as Pa)"
            .into(),
        warning: None,
        details: json!(
            found
                .iter()
                .map(|(p, v, _)| json!({"path": p, "value": v}))
                .collect::<Vec<_>>()
        ),
    };
    if !found.is_empty() {
        let texts: Vec<&str> = found.iter().map(|f| f.2.as_str()).collect();
        ind.warning = Some(format!(
            "{}; fdem takes consistent units (SI: Pa, kg/m^3, J/m^2, m): check these values",
            texts.join("; ")
        ));
    }
    ind
}
