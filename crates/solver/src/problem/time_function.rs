//! The time functions of loads, prescribed motions and walls: a condition's factor `f(t)`
//! (its `ramp`, or its `history`: [`crate::input::scene::load_history`]), its integral `F(t) = int_0^t f`
//! (the displacement of a prescribed velocity or a wall) and its rate `f'(t)` (the velocity
//! of a prescribed displacement).
//!
//! - A table `(t_k, f_k)` is linear between its points, `f_0` before the first and `f_n`
//!   after the last. Its integral is exact: on `(t_k, t_k+1]`,
//!   `F = C_k + f_k d + (f_k+1 - f_k) d^2 / (2 L)` with `d = t - t_k`, `L = t_k+1 - t_k`,
//!   `C_k = F(t_k)` summed by the trapezoid rule (exact for linear pieces); before the first
//!   point `F = f_0 t`; after the last `F = f_n t - (f_n t_n - C_n)`. These are the
//!   expressions of [`ramp_factor`] and [`ramp_integral`] for the table `[[0, 0], [T, 1]]`
//!   (and `[[0, 1]]` for a step), operation for operation, so that table gives the same bits
//!   as `"ramp": T`.
//! - A sine `m + a sin(w t + phi)`, `w = 2 pi / P`: `F = m t + (a/w)(cos(phi) - cos(w t + phi))`.
//! - A repeated table or sine with a number of cycles `n` ends at `t_e = t_0 + n P`, after
//!   which it holds `f(t_e)`: `F(t) = F(t_e) + f(t_e) (t - t_e)`. A repeated table in its
//!   cycle `m` (counted from 0): `F = F_table(t - m P) + m I_P`, `I_P` the integral of one
//!   period.
//!
//! Evaluation allocates nothing; a table is searched by bisection.

use crate::input::scene::load_history::{HistorySpec, Shape};

/// Ramp factor `min(1, t/ramp)`, 1 for a step.
pub fn ramp_factor(t: f64, ramp: f64) -> f64 {
    if ramp <= 0.0 {
        1.0
    } else {
        (t / ramp).min(1.0)
    }
}

/// Integral of the ramp factor from 0 to t (displacement of a ramped unit velocity).
pub fn ramp_integral(t: f64, ramp: f64) -> f64 {
    if ramp <= 0.0 {
        t
    } else if t <= ramp {
        0.5 * t * t / ramp
    } else {
        t - 0.5 * ramp
    }
}

/// A history ready to evaluate.
#[derive(Debug, Clone, PartialEq)]
pub struct History {
    kind: Kind,
    /// End of the cycles [s] (`f64::INFINITY`: none), after which `f` is held.
    end: f64,
    /// `f(end)` and `F(end)` (when `end` is finite).
    at_end: (f64, f64),
}

#[derive(Debug, Clone, PartialEq)]
enum Kind {
    /// A table, repeated with its period when `periodic`.
    Table { table: Table, periodic: bool },
    /// `mean + amplitude sin(omega t + phase)`.
    Sine {
        mean: f64,
        amplitude: f64,
        omega: f64,
        phase: f64,
    },
}

#[derive(Debug, Clone, PartialEq)]
struct Table {
    t: Vec<f64>,
    f: Vec<f64>,
    /// `F(t_k)`.
    c: Vec<f64>,
}

impl Table {
    fn new(pts: &[[f64; 2]]) -> Self {
        let t: Vec<f64> = pts.iter().map(|p| p[0]).collect();
        let f: Vec<f64> = pts.iter().map(|p| p[1]).collect();
        let mut c = Vec::with_capacity(t.len());
        if !t.is_empty() {
            c.push(f[0] * t[0]);
        }
        for k in 1..t.len() {
            c.push(c[k - 1] + 0.5 * (f[k - 1] + f[k]) * (t[k] - t[k - 1]));
        }
        Self { t, f, c }
    }

    /// The segment `k` with `t_k < t <= t_k+1`, or `None` before the first point (`t <= t_0`)
    /// and after the last (`t > t_n`).
    fn segment(&self, t: f64) -> Option<usize> {
        let n = self.t.len();
        if n < 2 || t <= self.t[0] || t > self.t[n - 1] {
            return None;
        }
        // the number of points strictly before t, at least 1
        let k = self.t.partition_point(|&tk| tk < t);
        Some(k - 1)
    }

    fn value(&self, t: f64) -> f64 {
        let n = self.t.len();
        if n == 0 {
            return 0.0;
        }
        match self.segment(t) {
            Some(k) => {
                let (df, len) = (self.f[k + 1] - self.f[k], self.t[k + 1] - self.t[k]);
                self.f[k] + df * (t - self.t[k]) / len
            }
            None if t <= self.t[0] => self.f[0],
            None => self.f[n - 1],
        }
    }

    fn integral(&self, t: f64) -> f64 {
        let n = self.t.len();
        if n == 0 {
            return 0.0;
        }
        match self.segment(t) {
            Some(k) => {
                let (df, len) = (self.f[k + 1] - self.f[k], self.t[k + 1] - self.t[k]);
                let d = t - self.t[k];
                self.c[k] + self.f[k] * d + 0.5 * df * d * d / len
            }
            None if t <= self.t[0] => self.f[0] * t,
            None => self.f[n - 1] * t - (self.f[n - 1] * self.t[n - 1] - self.c[n - 1]),
        }
    }

    fn rate(&self, t: f64) -> f64 {
        match self.segment(t) {
            Some(k) => (self.f[k + 1] - self.f[k]) / (self.t[k + 1] - self.t[k]),
            None => 0.0,
        }
    }

    fn period(&self) -> f64 {
        match (self.t.first(), self.t.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }
}

impl History {
    /// The evaluator of a checked history ([`crate::input::scene::load_history::check`]); an unchecked empty
    /// table evaluates to 0, never panics.
    pub fn new(spec: &HistorySpec) -> Self {
        let (kind, end) = match spec {
            HistorySpec::Table(pts) => (
                Kind::Table {
                    table: Table::new(pts),
                    periodic: false,
                },
                f64::INFINITY,
            ),
            HistorySpec::Shape(Shape::Steps(s)) => (
                Kind::Table {
                    table: Table::new(&s.table()),
                    periodic: false,
                },
                f64::INFINITY,
            ),
            HistorySpec::Shape(Shape::Repeat(r)) => {
                let table = Table::new(&r.table);
                let end = r.cycles.map_or(f64::INFINITY, |n| {
                    table.t.first().copied().unwrap_or(0.0) + n * table.period()
                });
                (
                    Kind::Table {
                        table,
                        periodic: true,
                    },
                    end,
                )
            }
            HistorySpec::Shape(Shape::Sine(s)) => (
                Kind::Sine {
                    mean: s.mean,
                    amplitude: s.amplitude,
                    omega: 2.0 * std::f64::consts::PI / s.period,
                    phase: s.phase_deg.to_radians(),
                },
                s.cycles.map_or(f64::INFINITY, |n| n * s.period),
            ),
        };
        let mut h = History {
            kind,
            end,
            at_end: (0.0, 0.0),
        };
        if end.is_finite() {
            h.at_end = (h.cyclic_value(end), h.cyclic_integral(end));
        }
        h
    }

    /// The factor `f(t)`.
    pub fn value(&self, t: f64) -> f64 {
        if t > self.end {
            self.at_end.0
        } else {
            self.cyclic_value(t)
        }
    }

    /// The integral `F(t) = int_0^t f`.
    pub fn integral(&self, t: f64) -> f64 {
        if t > self.end {
            self.at_end.1 + self.at_end.0 * (t - self.end)
        } else {
            self.cyclic_integral(t)
        }
    }

    /// The rate `f'(t)` (the slope of the piece that ends at `t` at a table's points).
    pub fn rate(&self, t: f64) -> f64 {
        if t > self.end {
            return 0.0;
        }
        match &self.kind {
            Kind::Table { table, periodic } => {
                let (tt, _) = self.in_period(table, *periodic, t);
                table.rate(tt)
            }
            Kind::Sine {
                amplitude,
                omega,
                phase,
                ..
            } => amplitude * omega * (omega * t + phase).cos(),
        }
    }

    /// The largest `|f|` over all times.
    pub fn max_abs(&self) -> f64 {
        match &self.kind {
            Kind::Table { table, .. } => table.f.iter().fold(0.0, |m, v| m.max(v.abs())),
            Kind::Sine {
                mean, amplitude, ..
            } => mean.abs() + amplitude.abs(),
        }
    }

    /// A time `t` of a repeated table moved into the first period, and the number of whole
    /// periods removed.
    fn in_period(&self, table: &Table, periodic: bool, t: f64) -> (f64, f64) {
        let p = table.period();
        if !periodic || p <= 0.0 || t <= table.t[table.t.len() - 1] {
            return (t, 0.0);
        }
        let t0 = table.t[0];
        let mut m = ((t - t0) / p).floor();
        let mut tt = t - m * p;
        // t on a period's end belongs to the period that ends there
        if tt <= t0 {
            m -= 1.0;
            tt += p;
        }
        (tt, m)
    }

    fn cyclic_value(&self, t: f64) -> f64 {
        match &self.kind {
            Kind::Table { table, periodic } => {
                let (tt, _) = self.in_period(table, *periodic, t);
                table.value(tt)
            }
            Kind::Sine {
                mean,
                amplitude,
                omega,
                phase,
            } => mean + amplitude * (omega * t + phase).sin(),
        }
    }

    fn cyclic_integral(&self, t: f64) -> f64 {
        match &self.kind {
            Kind::Table { table, periodic } => {
                let (tt, m) = self.in_period(table, *periodic, t);
                let one_period = match (table.c.first(), table.c.last()) {
                    (Some(a), Some(b)) => b - a,
                    _ => 0.0,
                };
                table.integral(tt) + m * one_period
            }
            Kind::Sine {
                mean,
                amplitude,
                omega,
                phase,
            } => mean * t + amplitude / omega * (phase.cos() - (omega * t + phase).cos()),
        }
    }
}

/// The factor at `t` of a condition with `ramp` and `history` (the history when given).
pub fn factor(t: f64, ramp: f64, history: Option<&History>) -> f64 {
    match history {
        Some(h) => h.value(t),
        None => ramp_factor(t, ramp),
    }
}

/// The integral of the factor from 0 to `t` (the history's when given).
pub fn integral(t: f64, ramp: f64, history: Option<&History>) -> f64 {
    match history {
        Some(h) => h.integral(t),
        None => ramp_integral(t, ramp),
    }
}

/// The rate of the factor at `t` (the history's when given; a ramp's `1/ramp` on
/// `(0, ramp]`).
pub fn rate(t: f64, ramp: f64, history: Option<&History>) -> f64 {
    match history {
        Some(h) => h.rate(t),
        None if ramp > 0.0 && t > 0.0 && t <= ramp => 1.0 / ramp,
        None => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::scene::load_history::{Repeat, Sine, Steps};

    fn table(p: &[[f64; 2]]) -> History {
        History::new(&HistorySpec::Table(p.to_vec()))
    }

    /// The table `[[0, 0], [T, 1]]` is the ramp `T`, bit for bit, factor and integral, at
    /// times before, inside, on the end of and after the ramp; `[[0, 1]]` is the step.
    #[test]
    fn ramp_table_gives_the_bits_of_the_ramp() {
        for ramp in [1e-3, 3.7e-4, 0.3, 7.0] {
            let h = table(&[[0.0, 0.0], [ramp, 1.0]]);
            for k in 0..2000 {
                let t = ramp * (k as f64 / 997.0) * 1.0000001;
                assert_eq!(h.value(t).to_bits(), ramp_factor(t, ramp).to_bits(), "{t}");
                assert_eq!(
                    h.integral(t).to_bits(),
                    ramp_integral(t, ramp).to_bits(),
                    "{t} {ramp}"
                );
            }
            for t in [0.0, ramp, 2.0 * ramp] {
                assert_eq!(h.integral(t).to_bits(), ramp_integral(t, ramp).to_bits());
            }
        }
        let step = table(&[[0.0, 1.0]]);
        for t in [0.0, 1e-9, 0.5, 3.0] {
            assert_eq!(step.value(t).to_bits(), ramp_factor(t, 0.0).to_bits());
            assert_eq!(step.integral(t).to_bits(), ramp_integral(t, 0.0).to_bits());
        }
    }

    /// The integral of a table against a fine midpoint sum (exact for linear pieces up to
    /// round-off: 1e-12), holding before and after, and its rate.
    #[test]
    fn table_integral_is_exact_and_holds_the_ends() {
        let pts = [[0.5, 2.0], [1.0, -1.0], [1.5, 3.0], [4.0, 3.0], [5.0, 0.0]];
        let h = table(&pts);
        assert_eq!(h.value(0.2), 2.0);
        assert_eq!(h.value(7.0), 0.0);
        assert_eq!(h.value(1.25), 1.0);
        assert_eq!(h.rate(1.25), 8.0);
        assert_eq!(h.rate(0.3), 0.0);
        let n = 200_000;
        let t_end = 6.0;
        let dt = t_end / n as f64;
        let mut sum = 0.0;
        let mut worst: f64 = 0.0;
        for k in 0..n {
            sum += h.value((k as f64 + 0.5) * dt) * dt;
            if (k + 1) % 20_000 == 0 {
                let t = (k + 1) as f64 * dt;
                let err = (h.integral(t) - sum).abs();
                assert!(err < 1e-9, "{t}: {} {sum}", h.integral(t));
                worst = worst.max(err);
            }
        }
        // by hand: 2*0.5 + (2-1)/2*0.5 + (-1+3)/2*0.5 + 3*2.5 + 3/2*1 + 0 = 10.75
        let by_hand = (h.integral(6.0) - 10.75).abs();
        assert!(by_hand < 1e-12);
        fdem_figures::record_part(
            68,
            1,
            format!(
                "table {} (by hand {})",
                fdem_figures::sci(worst, 1),
                fdem_figures::sci(by_hand, 1)
            ),
        );
    }

    /// A sine's integral in closed form against a fine midpoint sum, and its end.
    #[test]
    fn sine_integral_and_cycles() {
        let h = History::new(&HistorySpec::Shape(Shape::Sine(Sine {
            period: 0.4,
            amplitude: 2.0,
            mean: 0.5,
            phase_deg: 30.0,
            cycles: Some(2.25),
        })));
        let end = 0.9;
        let f_end = 0.5 + 2.0 * (2.0 * std::f64::consts::PI * 2.25 + 30f64.to_radians()).sin();
        assert!((h.value(1.3) - f_end).abs() < 1e-12);
        assert_eq!(h.rate(1.3), 0.0);
        let n = 400_000;
        let dt = 1.3 / n as f64;
        let mut sum = 0.0;
        for k in 0..n {
            sum += h.value((k as f64 + 0.5) * dt) * dt;
        }
        let err = (h.integral(1.3) - sum).abs();
        assert!(err < 1e-10, "{} {sum}", h.integral(1.3));
        assert!((h.integral(1.3) - h.integral(end) - f_end * 0.4).abs() < 1e-12);
        fdem_figures::record_part(68, 2, format!("sine {}", fdem_figures::sci(err, 1)));
    }

    /// A repeated triangle: its value and integral in the later cycles, and its end; the
    /// steps' table.
    #[test]
    fn repeat_and_steps() {
        let h = History::new(&HistorySpec::Shape(Shape::Repeat(Repeat {
            table: vec![[1.0, 0.0], [2.0, 1.0], [3.0, 0.0]],
            cycles: Some(2.5),
        })));
        // period 2 from t = 1: f(5.5) = f(3.5 - 2) = f(1.5) = 0.5, F(5) = 2 periods of 1
        assert_eq!(h.value(5.5), 0.5);
        assert_eq!(h.value(5.0), 0.0);
        let errs = [
            (h.integral(5.0) - 2.0).abs(),
            (h.integral(5.5) - 2.125).abs(),
        ];
        assert!(errs.iter().all(|e| *e < 1e-15), "{errs:?}");
        let repeat = errs[0].max(errs[1]);
        // ends at 1 + 2.5 * 2 = 6 with f = 1, F = 2.5
        assert_eq!(h.value(9.0), 1.0);
        assert!((h.integral(9.0) - (2.5 + 3.0)).abs() < 1e-12);
        assert_eq!(h.rate(5.5), 1.0);
        assert_eq!(h.rate(6.5), 0.0);
        let s = Steps {
            values: vec![0.5, 1.0, 0.0],
            rise: 0.1,
            hold: 1.0,
        };
        let pts = s.table();
        assert_eq!(pts.len(), 7);
        let h = History::new(&HistorySpec::Shape(Shape::Steps(s)));
        assert_eq!(h.value(0.6), 0.5);
        assert!((h.value(1.15) - 0.75).abs() < 1e-12);
        assert_eq!(h.value(10.0), 0.0);
        fdem_figures::record_part(68, 3, format!("repeat {}", fdem_figures::sci(repeat, 1)));
    }
}
