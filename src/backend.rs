//! The element and contact kernels an integrator calls, behind one interface
//! ([`Kernels`]): the CPU twins ([`CpuKernels`], f64) or the GPU
//! ([`crate::gpu::GpuKernels`], f32).

use crate::element::CornerLayout;
use crate::error::Result;
use crate::kernels::corotated_forces::{corotated_forces, turn_energy, Frames};
use crate::kernels::damage_data::{DamageData, DamageState, DamagedPoint};
use crate::kernels::damage_sieve::SieveMemory;
use crate::kernels::{
    as_vec3, as_vec3_mut, contact_gap, damage_forces, element_forces, mark_damaged, node_gather,
    slip_rate, ContactPoint, ContactQueries, ElementData, Incidence, KeptData,
};
use crate::material::damage::Dissipation;
use crate::model::Model;

/// What an integrator needs from the element and contact kernels.
pub trait Kernels {
    /// Name of the device the kernels run on ("cpu" or the adapter's name).
    fn device_name(&self) -> String;
    /// Relative accuracy of the kernels' arithmetic (1e-15 on the CPU, ~1e-7 for f32).
    fn unit_roundoff(&self) -> f64;
    /// Internal nodal forces $f = \int B^T \sigma(u)$ for the displacement `u` (3 per node).
    fn internal_forces_into(&mut self, u: &[f64], f: &mut [f64]) -> Result<()>;
    /// Closest-point projection, normal, gap and gap rate of every contact query.
    fn contact_gap_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        out: &mut [ContactPoint],
    ) -> Result<()>;
    /// Broad and narrow phase of every surface interface at (u, v): each query's candidates
    /// are the faces of its interface whose box, grown by `margin`, holds the node, and its
    /// point the closest of them (as [`Self::contact_gap_into`]). The default runs the host's
    /// grid (`search`, filling `queries`' candidate lists) and then
    /// `contact_gap_into`; the GPU runs the whole search on the device.
    #[allow(clippy::too_many_arguments)]
    fn contact_search_into(
        &mut self,
        model: &Model,
        u: &[f64],
        v: &[f64],
        margin: f64,
        queries: &mut ContactQueries,
        lists: &mut [Vec<u32>],
        out: &mut [ContactPoint],
    ) -> Result<()> {
        crate::search::surface_candidates(model, queries, lists, u, margin);
        self.contact_gap_into(u, v, queries, out)
    }
    /// Covariant slip rates of every contact point (zero where `face` is none).
    fn slip_rate_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        points: &[ContactPoint],
        out: &mut [[f64; 2]],
    ) -> Result<()>;
    /// An explicit step's internal forces: the plies' damage stepped over `dt` to `u` (from
    /// $u - \Delta t\, v$, `v` the step's mid-step velocities), then the forces with it (the
    /// same as [`Self::internal_forces_into`] where nothing damages). Returns the energy the
    /// damage dissipated over the step, with the fibre modes' share.
    fn step_forces_into(
        &mut self,
        (u, _v): (&[f64], &[f64]),
        _dt: f64,
        f: &mut [f64],
    ) -> Result<Dissipation> {
        self.internal_forces_into(u, f)?;
        Ok(Dissipation::default())
    }
    /// The damage state (a checkpoint's part): empty where nothing damages.
    fn damage_values(&self) -> Result<Vec<f64>> {
        Ok(Vec::new())
    }
    /// Where the elements' forces are corotated, what $\tfrac12 u^n \cdot f$ holds beyond
    /// their strain energy at the last forces ([`crate::element::corotation::turn_energy`]
    /// summed); zero for linear kinematics.
    fn turn_energy(&self) -> f64 {
        0.0
    }
    /// Continues from a checkpoint's damage state.
    fn restore_damage(&mut self, values: &[f64]) -> std::result::Result<(), String> {
        match values.is_empty() {
            true => Ok(()),
            false => Err("the checkpoint holds ply damage and this model has none".into()),
        }
    }
    /// Each element's acting damage by mode, the largest over its points (frames), and the
    /// first damaged point; `None` where nothing damages.
    fn damage_cells(&self) -> Option<(Vec<[f64; 4]>, Option<DamagedPoint>)> {
        None
    }
}

/// The kernels on the CPU, in f64.
pub struct CpuKernels {
    data: ElementData,
    /// Where each corner's force lives, and what the force kernels keep (both fixed).
    layout: CornerLayout,
    kept: KeptData,
    incidence: Incidence,
    corner_forces: Vec<[f64; 3]>,
    /// The plies' damage, its state and the sieve's memory, where any element damages.
    damage: Option<(DamageData, DamageState, SieveMemory)>,
    /// The damaged elements, per block: the damage pass gives their forces.
    damaged: Vec<Vec<bool>>,
    /// The elements' frames, where the kinematics is corotational
    /// ([`crate::kernels::corotated_forces`]), and the last forces' turn energy.
    frames: Option<Box<(Frames, f64)>>,
}

impl CpuKernels {
    pub fn new(data: ElementData) -> Self {
        let incidence = Incidence::new(&data.elements, data.reference.len());
        let corner_forces = vec![[0.0; 3]; data.corner_count()];
        CpuKernels {
            layout: data.layout(),
            kept: KeptData::of(&data),
            data,
            incidence,
            corner_forces,
            damage: None,
            damaged: Vec::new(),
            frames: None,
        }
    }

    /// With each element's forces in its own frame (`run.kinematics = "corotational"`).
    pub fn corotational(mut self, on: bool) -> Self {
        self.frames = on.then(|| Box::new((Frames::new(&self.data), 0.0)));
        self
    }

    /// With the plies' damage (none where no element damages).
    pub fn with_damage(mut self, damage: Option<DamageData>) -> Self {
        self.damage = damage.filter(DamageData::any).map(|d| {
            let (s, m) = (DamageState::new(&d), SieveMemory::new(&d));
            (d, s, m)
        });
        self
    }

    /// The element forces at `u` and, with damage, its pass (see
    /// [`Kernels::step_forces_into`]), gathered into `f`.
    fn forces(
        &mut self,
        (u, v): (&[f64], &[f64]),
        f: &mut [f64],
        (dt, advance): (f64, bool),
    ) -> Dissipation {
        let fixed = (&self.layout, &self.kept);
        if let Some((d, s, _)) = &self.damage {
            mark_damaged(&self.data, (d, s), &mut self.damaged);
        }
        let (u3, skip) = (as_vec3(u), self.damaged.as_slice());
        match self.frames.as_deref_mut() {
            Some((frames, _)) => corotated_forces(
                &self.data,
                fixed,
                u3,
                &mut self.corner_forces,
                (skip, frames),
            ),
            None => element_forces(&self.data, fixed, u3, &mut self.corner_forces, skip),
        }
        let frames = self.frames.as_deref().map(|(f, _)| f);
        let dissipated = match &mut self.damage {
            Some((d, s, m)) => damage_forces(
                &self.data,
                (d, s, m),
                (&self.layout, frames),
                (as_vec3(u), as_vec3(v)),
                &mut self.corner_forces,
                (dt, advance),
            ),
            None => Dissipation::default(),
        };
        if let Some((frames, energy)) = self.frames.as_deref_mut() {
            *energy = turn_energy(&self.data, &self.layout, &self.corner_forces, frames);
        }
        node_gather(&self.incidence, &self.corner_forces, as_vec3_mut(f));
        dissipated
    }

    pub fn data(&self) -> &ElementData {
        &self.data
    }

    /// The corner forces of the last [`Kernels::internal_forces_into`], in the twins'
    /// [`crate::element::CornerLayout`].
    pub fn corner_forces(&self) -> &[[f64; 3]] {
        &self.corner_forces
    }
}

impl Kernels for CpuKernels {
    fn device_name(&self) -> String {
        "cpu".into()
    }
    fn unit_roundoff(&self) -> f64 {
        f64::EPSILON
    }
    fn internal_forces_into(&mut self, u: &[f64], f: &mut [f64]) -> Result<()> {
        self.forces((u, u), f, (0.0, false));
        Ok(())
    }
    fn step_forces_into(
        &mut self,
        uv: (&[f64], &[f64]),
        dt: f64,
        f: &mut [f64],
    ) -> Result<Dissipation> {
        Ok(self.forces(uv, f, (dt, true)))
    }
    fn turn_energy(&self) -> f64 {
        self.frames.as_deref().map_or(0.0, |(_, e)| *e)
    }
    fn damage_values(&self) -> Result<Vec<f64>> {
        Ok(self
            .damage
            .as_ref()
            .map(|(_, s, _)| s.flat())
            .unwrap_or_default())
    }
    fn restore_damage(&mut self, values: &[f64]) -> std::result::Result<(), String> {
        match &mut self.damage {
            Some((d, s, m)) => {
                // a resumed run's sieve starts afresh (it never changes the forces)
                *m = SieveMemory::new(d);
                s.restore(d, values)
            }
            None if values.is_empty() => Ok(()),
            None => Err("the checkpoint holds ply damage and this model has none".into()),
        }
    }
    fn damage_cells(&self) -> Option<(Vec<[f64; 4]>, Option<DamagedPoint>)> {
        let (d, s, _) = self.damage.as_ref()?;
        let blocks = crate::kernels::damage_data::block_counts(&self.data.elements);
        Some((s.cells(d, &blocks), s.first_damaged(d, &blocks)))
    }
    fn contact_gap_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        out: &mut [ContactPoint],
    ) -> Result<()> {
        contact_gap(&self.data.reference, as_vec3(u), as_vec3(v), queries, out);
        Ok(())
    }
    fn slip_rate_into(
        &mut self,
        u: &[f64],
        v: &[f64],
        queries: &ContactQueries,
        points: &[ContactPoint],
        out: &mut [[f64; 2]],
    ) -> Result<()> {
        slip_rate(
            &self.data.reference,
            as_vec3(u),
            as_vec3(v),
            queries,
            points,
            out,
        );
        Ok(())
    }
}
