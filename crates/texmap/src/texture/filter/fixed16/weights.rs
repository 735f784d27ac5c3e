//! The probes' 15-bit weights, made once per probe count: anisotropic filtering and `ewa`
//! place their probes and weight them by the count alone, so a read looks its probes up
//! instead of rounding a running sum of weights probe by probe.

use super::ONE;

/// The most probes a read takes (anisotropic filtering's 16 taps, `ewa`'s `MAX_PROBES`).
pub(in super::super) const MAX_PROBES: usize = 16;

/// A probe of [`super::read_probes`]: its place `t` along the axis (the read at
/// `uv + t·step`) and its share of the 15-bit total. (In this order: the AVX2 reads load
/// two probes as one 16-byte vector, their weights in lanes 1 and 3.)
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub(in super::super) struct Probe {
    pub t: f32,
    pub weight: i32,
}

impl Probe {
    /// One probe at the centre, weighing all.
    pub(in super::super) const WHOLE: Probe = Probe {
        t: 0.0,
        weight: ONE,
    };
}

/// `probes` (`(t, w)`, the float weights summing to 1) with 15-bit weights: probe `i`'s is
/// what the running sum of the float weights adds when rounded, so the weights sum to exactly
/// [`ONE`] (a NaN sum counts as 0). Only the first `probes.len()` are set.
#[must_use]
pub(in super::super) fn fixed(probes: &[(f32, f32)]) -> [Probe; MAX_PROBES] {
    let mut out = [Probe::default(); MAX_PROBES];
    let (mut running, mut given) = (0.0f32, 0);
    for (o, &(t, w)) in out.iter_mut().zip(probes) {
        running += w;
        // `max` then `min`, not `clamp`: a NaN sum becomes 0, where `clamp` would keep it.
        #[allow(clippy::manual_clamp)]
        let upto = (running.max(0.0).min(1.0) * ONE as f32).round() as i32;
        *o = Probe {
            t,
            weight: upto - given,
        };
        given = upto;
    }
    out
}

/// The fixed probes of every count from 1 to [`MAX_PROBES`] of one layout.
pub(in super::super) struct ProbeSets([[Probe; MAX_PROBES]; MAX_PROBES]);

impl ProbeSets {
    /// The sets of `layout(count)`: the first `count` probes `(t, w)` of `count`.
    pub(in super::super) fn new(layout: impl Fn(usize) -> [(f32, f32); MAX_PROBES]) -> Self {
        ProbeSets(std::array::from_fn(|i| fixed(&layout(i + 1)[..=i])))
    }

    /// The `count` probes of `count` (1 to [`MAX_PROBES`]).
    ///
    /// # Panics
    /// If `count` is 0 or above [`MAX_PROBES`].
    #[inline(always)]
    pub(in super::super) fn get(&self, count: usize) -> &[Probe] {
        &self.0[count - 1][..count]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_sets_weights_sum_to_one_and_follow_the_running_sum() {
        let sets = ProbeSets::new(|n| {
            let mut p = [(0.0, 0.0); MAX_PROBES];
            for (i, p) in p.iter_mut().enumerate().take(n) {
                *p = (i as f32, 1.0 / n as f32);
            }
            p
        });
        for n in 1..=MAX_PROBES {
            let probes = sets.get(n);
            assert_eq!(probes.len(), n);
            assert_eq!(
                probes.iter().map(|p| p.weight).sum::<i32>(),
                ONE,
                "{n} probes"
            );
            let mut running = 0.0f32;
            let mut before = 0;
            for (i, p) in probes.iter().enumerate() {
                assert_eq!(p.t, i as f32);
                running += 1.0 / n as f32;
                let upto = (running.min(1.0) * ONE as f32).round() as i32;
                assert_eq!(p.weight, upto - before, "probe {i} of {n}");
                before = upto;
            }
        }
    }

    #[test]
    fn a_nan_weight_counts_as_nothing() {
        let p = fixed(&[(0.0, 0.5), (0.5, f32::NAN), (1.0, 0.5)]);
        assert_eq!(p[0].weight, (0.5 * ONE as f32).round() as i32);
        assert_eq!(p[1].weight, -p[0].weight);
        assert_eq!(p[2].weight, 0);
        assert_eq!(Probe::WHOLE, fixed(&[(0.0, 1.0)])[0]);
    }
}
