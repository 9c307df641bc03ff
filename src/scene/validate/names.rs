//! Names: what a scene may call its materials, bodies, contacts, planes and probes.
//!
//! A name becomes part of a history column (`bar.vx`), a CSV header, a summary entry and,
//! for VTU frames, XML. So a name is non-empty and made of ASCII letters, digits, `_`, `-`
//! and `.`; and the kinds that make history columns (bodies, contacts, rigid planes, rigid
//! bodies, probes, named fixes) share one set of names, so that no two columns are alike.

use super::Checker;
use crate::error::Result;
use crate::scene::raw::RawScene;

/// Whether `c` may appear in a name.
fn allowed(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')
}

impl Checker<'_> {
    /// Every name of the scene: well formed, and unique within its namespace.
    pub(super) fn names(&self, raw: &RawScene) -> Result<()> {
        let materials = raw.material.iter().map(|m| ("material", m.name.as_str()));
        for (i, (kind, name)) in materials.enumerate() {
            self.name_well_formed(&format!("{kind}[{i}].name"), name)?;
        }
        // the kinds whose names head history columns
        let columns: Vec<(&str, usize, &str)> = (raw.body.iter().enumerate())
            .map(|(i, b)| ("body", i, b.name.as_str()))
            .chain((raw.contact.iter().enumerate()).map(|(i, c)| ("contact", i, c.name.as_str())))
            .chain(
                (raw.rigid_plane.iter().enumerate())
                    .map(|(i, p)| ("rigid_plane", i, p.name.as_str())),
            )
            .chain(
                (raw.rigid_body.iter().enumerate())
                    .map(|(i, b)| ("rigid_body", i, b.name.as_str())),
            )
            .chain((raw.probe.iter().enumerate()).map(|(i, p)| ("probe", i, p.name.as_str())))
            .chain(
                (raw.fix.iter().enumerate())
                    .filter_map(|(i, f)| Some(("fix", i, f.name.as_deref()?))),
            )
            .chain((raw.cohesive.iter().enumerate()).map(|(i, c)| ("cohesive", i, c.name.as_str())))
            .collect();
        let mut seen = std::collections::HashMap::new();
        for &(kind, i, name) in &columns {
            let key = format!("{kind}[{i}].name");
            self.name_well_formed(&key, name)?;
            if let Some((k, j)) = seen.insert(name, (kind, i)) {
                return Err(self.err(
                    key,
                    format!(
                        "`{name}` is also the name of {k}[{j}]: bodies, contacts, rigid planes, rigid bodies, probes, named fixes and cohesive interfaces name history columns, so their names must differ"
                    ),
                ));
            }
        }
        Ok(())
    }

    pub(super) fn name_well_formed(&self, key: &str, name: &str) -> Result<()> {
        if name.is_empty() {
            return Err(self.err(key, "must not be empty"));
        }
        if let Some(c) = name.chars().find(|&c| !allowed(c)) {
            return Err(self.err(
                key,
                format!(
                    "{name:?} holds {c:?}: a name is made of ASCII letters, digits, `_`, `-` and `.` (it heads history columns and names files)"
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::allowed;

    #[test]
    fn the_allowed_characters() {
        assert!("bar_A-1.top".chars().all(allowed));
        for c in [',', '"', '\n', ' ', '&', '<', '/', 'é', '\u{feff}'] {
            assert!(!allowed(c), "{c:?}");
        }
    }
}
