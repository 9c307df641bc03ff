//! The cohesive law of an interface between plies or bodies: a mixed-mode bilinear
//! traction-separation law (Camanho & Dávila 2002; Turon et al. 2006) with one penalty
//! stiffness K, the Benzeggagh-Kenane (BK) criterion for the mixed-mode toughness, and
//! irreversible damage.
//!
//! At a separation $\delta$ (the upper face's displacement less the lower's) across a unit
//! normal n, $\delta_n = \delta \cdot n$ opens the interface and $\delta_s = \delta - \delta_n
//! n$ slides it. The equivalent separation is $\lambda = \sqrt{\langle\delta_n\rangle^2 +
//! |\delta_s|^2}$ and the mixity $B = |\delta_s|^2 / \lambda^2$. With the pure modes' onsets
//! $\delta_n^0 = N / K$ and $\delta_s^0 = S / K$ (N, S the strengths):
//! - onset: $\lambda_0^2 = (\delta_n^0)^2 + ((\delta_s^0)^2 - (\delta_n^0)^2) B^\eta$;
//! - toughness: $G_c = G_{Ic} + (G_{IIc} - G_{Ic}) B^\eta$;
//! - final separation: $\lambda_f = 2 G_c / (K \lambda_0)$;
//! - damage: $d = \lambda_f (\lambda - \lambda_0) / (\lambda (\lambda_f - \lambda_0))$ in [0, 1],
//!   never less than before.
//!
//! The traction is $t = (1 - d) K (\langle\delta_n\rangle n + \delta_s) + K \min(\delta_n, 0)
//! n$: in compression the faces do not pass through each other, damaged or not. Along a
//! path of fixed mixity the damage d is reached at $r(d) = \lambda_f \lambda_0 / (\lambda_f -
//! d (\lambda_f - \lambda_0))$ and the energy dissipated per unit area is $G_c (r(d) -
//! \lambda_0) / (\lambda_f - \lambda_0)$, which is $G_c$ at full separation: a step's
//! dissipation is that difference between its damages, at the step's mixity.
//!
//! **Friction** (`friction` mu > 0, [`CohesiveLaw::step_sliding`]): where the faces press
//! on each other, at pressure $p = K \langle -\delta_n \rangle$, the damaged share d of the
//! interface resists sliding by Coulomb friction (Alfano and Sacco 2006): $t \mathrel{+}= d\,
//! t_f$ with $t_f = K (\delta_s - s)$, $|t_f| \le \mu p$, s the pair's slip (its return map
//! moves it where the trial exceeds the cone; it follows $\delta_s$ where the faces are
//! apart or undamaged). The pair stores $\tfrac12 d K |\delta_s - s|^2$ in its friction
//! spring, and the step dissipates $d\, t_f \cdot \Delta s - \tfrac12 \Delta d\, K
//! |\delta_s - s|^2$ by friction (the spring's share of the energy the damage's growth
//! releases stays stored).

/// The law's constants.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CohesiveLaw {
    /// Penalty stiffness K (stress per length).
    pub stiffness: f64,
    /// Onset tractions: normal N and shear S.
    pub strength: [f64; 2],
    /// Toughness: G_Ic and G_IIc (energy per area).
    pub toughness: [f64; 2],
    /// The BK exponent eta.
    pub bk: f64,
    /// Coulomb's coefficient between the damaged share's faces where they press (0: none).
    #[serde(default)]
    pub friction: f64,
}

/// What a point of the interface gives back for a separation: its traction (on the upper
/// face, from the lower) in the global axes, its damage after the step and the energy per
/// unit area the step dissipated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CohesiveStep {
    pub traction: [f64; 3],
    pub damage: f64,
    pub dissipated: f64,
}

/// [`CohesiveStep`] with friction ([`CohesiveLaw::step_sliding`]): the step (its traction
/// with the friction's), the pair's slip after it, the energy per unit area friction
/// dissipated over the step, and the pair's stored energy less half its traction's work on
/// the separation, $-\tfrac12 d\, t_f \cdot s$, per unit area (so that $\tfrac12 t \cdot \delta$
/// plus it is what the pair stores).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlidingStep {
    pub step: CohesiveStep,
    pub slip: [f64; 3],
    pub friction: f64,
    pub stored_offset: f64,
}

impl SlidingStep {
    /// A step of a law without friction: no slip, friction or offset.
    pub fn without_friction(step: CohesiveStep) -> Self {
        SlidingStep {
            step,
            slip: [0.0; 3],
            friction: 0.0,
            stored_offset: 0.0,
        }
    }
}

impl CohesiveLaw {
    /// The stiffness below which a pure mode would snap back ($\lambda_f \le \lambda_0$):
    /// $\max(N^2 / 2 G_{Ic}, S^2 / 2 G_{IIc})$. K must exceed it.
    pub fn snap_back_stiffness(&self) -> f64 {
        let [n, s] = self.strength;
        let [gi, gii] = self.toughness;
        (n * n / (2.0 * gi)).max(s * s / (2.0 * gii))
    }

    /// The onset and final separations $(\lambda_0, \lambda_f)$ and the toughness $G_c$ at
    /// mixity `b`.
    pub fn envelope(&self, b: f64) -> (f64, f64, f64) {
        let k = self.stiffness;
        let (dn, ds) = (self.strength[0] / k, self.strength[1] / k);
        let w = if b > 0.0 { b.powf(self.bk) } else { 0.0 };
        let l0 = (dn * dn + (ds * ds - dn * dn) * w).sqrt();
        let gc = self.toughness[0] + (self.toughness[1] - self.toughness[0]) * w;
        (l0, 2.0 * gc / (k * l0), gc)
    }

    /// The energy per unit area dissipated in reaching damage `d` along mixity `b`.
    fn dissipated_at(&self, d: f64, b: f64) -> f64 {
        let (l0, lf, gc) = self.envelope(b);
        let r = lf * l0 / (lf - d * (lf - l0));
        gc * (r - l0) / (lf - l0)
    }

    /// The traction at separation `delta` across unit normal `n`, from damage `d_old`.
    pub fn step(&self, delta: [f64; 3], n: [f64; 3], d_old: f64) -> CohesiveStep {
        let dn = delta[0] * n[0] + delta[1] * n[1] + delta[2] * n[2];
        let ds: [f64; 3] = std::array::from_fn(|a| delta[a] - dn * n[a]);
        let open = dn.max(0.0);
        let slide2 = ds[0] * ds[0] + ds[1] * ds[1] + ds[2] * ds[2];
        let lambda2 = open * open + slide2;
        let b = if lambda2 > 0.0 { slide2 / lambda2 } else { 0.0 };
        let (l0, lf, _) = self.envelope(b);
        let lambda = lambda2.sqrt();
        let d_now = match lambda > l0 {
            true => (lf * (lambda - l0) / (lambda * (lf - l0))).min(1.0),
            false => 0.0,
        };
        let d = d_old.max(d_now);
        let dissipated = match d > d_old {
            true => self.dissipated_at(d, b) - self.dissipated_at(d_old, b),
            false => 0.0,
        };
        let k = self.stiffness;
        let closed = k * dn.min(0.0);
        let traction =
            std::array::from_fn(|a| (1.0 - d) * k * (open * n[a] + ds[a]) + closed * n[a]);
        CohesiveStep {
            traction,
            damage: d,
            dissipated,
        }
    }

    /// [`Self::step`] with friction (module docs) from the pair's slip `slip` before the
    /// step.
    pub fn step_sliding(
        &self,
        delta: [f64; 3],
        n: [f64; 3],
        (d_old, slip): (f64, [f64; 3]),
    ) -> SlidingStep {
        let mut step = self.step(delta, n, d_old);
        let dn = delta[0] * n[0] + delta[1] * n[1] + delta[2] * n[2];
        let ds: [f64; 3] = std::array::from_fn(|a| delta[a] - dn * n[a]);
        let (k, d) = (self.stiffness, step.damage);
        let limit = self.friction * k * (-dn).max(0.0);
        if limit <= 0.0 || d <= 0.0 {
            // apart (or bonded): the faces stick afresh wherever they next press
            return SlidingStep {
                slip: ds,
                ..SlidingStep::without_friction(step)
            };
        }
        let trial: [f64; 3] = std::array::from_fn(|a| k * (ds[a] - slip[a]));
        let size = vector_norm(trial);
        let (t_f, slip_new) = match size > limit {
            true => {
                let t: [f64; 3] = trial.map(|x| x * limit / size);
                (t, std::array::from_fn(|a| ds[a] - t[a] / k))
            }
            false => (trial, slip),
        };
        let stretch2 = (0..3).map(|a| (ds[a] - slip_new[a]).powi(2)).sum::<f64>();
        let slid: f64 = (0..3).map(|a| t_f[a] * (slip_new[a] - slip[a])).sum();
        for (t, f) in step.traction.iter_mut().zip(t_f) {
            *t += d * f;
        }
        SlidingStep {
            step,
            slip: slip_new,
            friction: d * slid - 0.5 * (d - d_old) * k * stretch2,
            stored_offset: -0.5 * d * (0..3).map(|a| t_f[a] * slip_new[a]).sum::<f64>(),
        }
    }
}

fn vector_norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// IM7/8552 (NASA CompDam's constants), K = 1e5 N/mm^3.
    fn im7() -> CohesiveLaw {
        CohesiveLaw {
            stiffness: 1e5,
            strength: [60.0, 90.0],
            toughness: [0.277, 0.788],
            bk: 2.1,
            friction: 0.0,
        }
    }

    /// Opens (or slides) monotonically in many steps along `dir` and sums the work of the
    /// traction (trapezoid) and the law's dissipation.
    fn path(law: &CohesiveLaw, dir: [f64; 3], n: [f64; 3], to: f64, steps: usize) -> (f64, f64) {
        let (mut d, mut work, mut dissipated) = (0.0, 0.0, 0.0);
        let mut t_old = [0.0; 3];
        for i in 1..=steps {
            let s = to * i as f64 / steps as f64;
            let r = law.step(dir.map(|x| x * s), n, d);
            let ds = to / steps as f64;
            work += 0.5
                * (0..3)
                    .map(|a| (r.traction[a] + t_old[a]) * dir[a] * ds)
                    .sum::<f64>();
            t_old = r.traction;
            d = r.damage;
            dissipated += r.dissipated;
        }
        (work, dissipated)
    }

    #[test]
    fn each_pure_mode_dissipates_its_toughness_and_peaks_at_its_strength() {
        let law = im7();
        let n = [0.0, 0.0, 1.0];
        for (dir, g, strength) in [
            ([0.0, 0.0, 1.0], 0.277, 60.0),
            ([0.6, 0.8, 0.0], 0.788, 90.0),
        ] {
            let (l0, lf, _) = law.envelope(if dir[2] > 0.0 { 0.0 } else { 1.0 });
            let (work, dissipated) = path(&law, dir, n, 1.2 * lf, 20_000);
            assert!((work / g - 1.0).abs() < 1e-3, "work {work} against {g}");
            assert!(
                (dissipated / g - 1.0).abs() < 1e-12,
                "dissipated {dissipated}"
            );
            let peak = law.step(dir.map(|x| x * l0), n, 0.0).traction;
            let t = (peak[0] * peak[0] + peak[1] * peak[1] + peak[2] * peak[2]).sqrt();
            assert!((t / strength - 1.0).abs() < 1e-12, "{t}");
        }
    }

    #[test]
    fn a_mixed_mode_dissipates_the_bk_toughness() {
        let law = im7();
        let n = [0.0, 0.0, 1.0];
        // opening and sliding alike: B = 1/2
        let dir = [
            std::f64::consts::FRAC_1_SQRT_2,
            0.0,
            std::f64::consts::FRAC_1_SQRT_2,
        ];
        let gc = 0.277 + (0.788 - 0.277) * 0.5f64.powf(2.1);
        let (_, lf, g) = law.envelope(0.5);
        assert!((g - gc).abs() < 1e-15);
        let (work, dissipated) = path(&law, dir, n, 1.1 * lf, 20_000);
        assert!((work / gc - 1.0).abs() < 1e-3, "{work} against {gc}");
        assert!((dissipated / gc - 1.0).abs() < 1e-12);
    }

    /// A path of `steps` separations through `points` (piecewise linear), stepped with
    /// friction: the traction's work (trapezoid), and at the end what the pair stores
    /// ($\tfrac12 t \cdot \delta$ plus the offset) and what it dissipated (damage and
    /// friction), with the last step.
    fn sliding_path(
        law: &CohesiveLaw,
        points: &[[f64; 3]],
        steps: usize,
    ) -> (f64, f64, f64, SlidingStep) {
        let n = [0.0, 0.0, 1.0];
        let (mut d, mut slip, mut work, mut dissipated) = (0.0, [0.0; 3], 0.0, 0.0);
        let (mut t_old, mut x_old) = ([0.0; 3], points[0]);
        let mut last = SlidingStep::without_friction(law.step(points[0], n, 0.0));
        for w in points.windows(2) {
            for i in 1..=steps {
                let s = i as f64 / steps as f64;
                let x: [f64; 3] = std::array::from_fn(|a| w[0][a] + s * (w[1][a] - w[0][a]));
                last = law.step_sliding(x, n, (d, slip));
                let t = last.step.traction;
                work += 0.5
                    * (0..3)
                        .map(|a| (t[a] + t_old[a]) * (x[a] - x_old[a]))
                        .sum::<f64>();
                (t_old, x_old, d, slip) = (t, x, last.step.damage, last.slip);
                dissipated += last.step.dissipated + last.friction;
            }
        }
        let x = x_old;
        let stored = 0.5 * (0..3).map(|a| t_old[a] * x[a]).sum::<f64>() + last.stored_offset;
        (work, stored, dissipated, last)
    }

    /// Pressed, broken in shear, then slid on, back and forth: the friction caps the
    /// tangential traction at d mu p, and the traction's work is what the pair stores plus
    /// what it dissipated, within the trapezoid's error (4e-5 measured).
    #[test]
    fn friction_caps_the_sliding_traction_and_keeps_the_energy() {
        let law = CohesiveLaw {
            friction: 0.4,
            ..im7()
        };
        let press = -5e-4; // a pressure of 50 MPa
        let (_, lf, _) = law.envelope(1.0);
        let path = [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, press],
            [1.5 * lf, 0.0, press],
            [0.5 * lf, 0.3 * lf, press],
            [0.5 * lf, 0.3 * lf, 0.2 * lf],
            [0.0, 0.0, press],
        ];
        for upto in 3..=path.len() {
            let (work, stored, dissipated, last) = sliding_path(&law, &path[..upto], 4000);
            let scale = work.abs().max(dissipated);
            assert!(
                (work - stored - dissipated).abs() < 2e-4 * scale,
                "to point {upto}: work {work}, stored {stored}, dissipated {dissipated}"
            );
            assert!(dissipated > 0.0);
            if upto == 3 {
                // separated and sliding: the traction is mu p along the slide
                assert_eq!(last.step.damage, 1.0);
                let t = last.step.traction;
                let p = -law.stiffness * press;
                assert!((t[0] / (0.4 * p) - 1.0).abs() < 1e-12, "{t:?}");
                assert!(t[1].abs() < 1e-9 && (t[2] + p).abs() < 1e-9 * p);
            }
        }
        // apart, a separated pair carries nothing, and forgets its slip
        let open = law.step_sliding([0.1, 0.0, 1e-3], [0.0, 0.0, 1.0], (1.0, [0.5, 0.0, 0.0]));
        assert_eq!(open.step.traction, [0.0; 3]);
        assert_eq!((open.slip, open.friction), ([0.1, 0.0, 0.0], 0.0));
    }

    #[test]
    fn compression_holds_the_faces_apart_and_damage_never_heals() {
        let law = im7();
        let n = [0.0, 0.0, 1.0];
        let r = law.step([0.0, 0.0, -1e-3], n, 0.0);
        assert_eq!(r.damage, 0.0);
        assert_eq!(r.traction, [0.0, 0.0, -100.0]);
        // fully separated: no tension, the same resistance to closing
        let r = law.step([0.0, 0.0, -1e-3], n, 1.0);
        assert_eq!(r.traction, [0.0, 0.0, -100.0]);
        let r = law.step([0.0, 0.0, 1e-3], n, 1.0);
        assert_eq!((r.traction, r.dissipated), ([0.0; 3], 0.0));
        // a partly damaged point unloaded and reloaded below its damage keeps it
        let (l0, lf, _) = law.envelope(0.0);
        let d = law.step([0.0, 0.0, 0.5 * (l0 + lf)], n, 0.0).damage;
        assert!(d > 0.0 && d < 1.0);
        let r = law.step([0.0, 0.0, 0.5 * l0], n, d);
        assert_eq!((r.damage, r.dissipated), (d, 0.0));
        assert!((r.traction[2] - (1.0 - d) * 1e5 * 0.5 * l0).abs() < 1e-12);
    }
}
