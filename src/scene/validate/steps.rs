//! `[[step]]`: the steps after the first, each starting where the last one ended.

use super::*;

impl Checker<'_> {
    /// Each step's start: after the last one's, and on a whole
    /// number of `run.time_step`s (so that the run's steps land on it); and what it removes.
    pub(super) fn steps(
        &self,
        raw: &[RawStep],
        run: &RunSettings,
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<Vec<StepSpec>> {
        let mut out: Vec<StepSpec> = Vec::with_capacity(raw.len());
        for (i, s) in raw.iter().enumerate() {
            let key = |k: &str| format!("step[{i}].{k}");
            let start = self.positive(&key("start"), s.start)?;
            let last = out.last().map_or(0.0, |p| p.start);
            // a step at or after the end time never starts (a run stopped early and then
            // resumed with a later end time reaches it)
            if start <= last {
                return Err(self.err(
                    key("start"),
                    format!("{start}: a step starts after the one before it (at {last})"),
                ));
            }
            let Some(dt) = run.time_step else {
                return Err(self.err(
                    key("start"),
                    "a run of steps needs run.time_step, on whose multiples the steps start",
                ));
            };
            let whole = start / dt;
            if (whole - whole.round()).abs() > 1e-9 * whole.max(1.0) {
                return Err(self.err(
                    key("start"),
                    format!("{start} is not a whole number of run.time_step = {dt}: the run's steps must land on it"),
                ));
            }
            let remove_equations = match &s.remove_equations {
                None => Removal::None,
                Some(RawRemoval::All(a)) if a == "all" => Removal::All,
                Some(RawRemoval::All(a)) => {
                    return Err(self.err(
                        key("remove_equations"),
                        format!(
                            "`{a}`: give \"all\" or a list of {{ body, set or region, component }}"
                        ),
                    ));
                }
                Some(RawRemoval::Dofs(dofs)) => {
                    Removal::Dofs(self.removed_dofs(i, dofs, raw_bodies, bodies)?)
                }
            };
            out.push(StepSpec {
                start,
                remove_equations,
            });
        }
        Ok(out)
    }

    /// The dependent dofs a step's `remove_equations` names.
    fn removed_dofs(
        &self,
        i: usize,
        dofs: &[RawDof],
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<Vec<(usize, NodeSelection, usize)>> {
        let mut out = Vec::with_capacity(dofs.len());
        for (j, d) in dofs.iter().enumerate() {
            let key = |k: &str| format!("step[{i}].remove_equations[{j}].{k}");
            let body = self.body_index(&key("body"), &d.body, raw_bodies)?;
            if d.set.is_none() && d.region.is_none() {
                return Err(self.err(key("set"), "give the nodes by `set` or `region`"));
            }
            let nodes = self.nodes_of(&key, (&None, &d.set, d.region.as_ref()), &bodies[body])?;
            let component = self.component(&key("component"), &d.component)?;
            out.push((body, nodes, component));
        }
        Ok(out)
    }
}
