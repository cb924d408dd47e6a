//! Load combinations: `[combinations.<name>]` tables that override keys of the scene's
//! `[boundary.*]`, `[loads]` and `[uplift]` (water levels, drains, the pseudo-static
//! acceleration), so that one scene file holds the usual, flood and extreme cases of a dam.

use super::{Scene, SceneError};
use std::path::PathBuf;

/// The tables a combination may override: the loads, not the geometry, mesh or joint.
const OVERRIDABLE: [&str; 3] = ["boundary", "loads", "uplift"];

impl Scene {
    /// The names of the scene's load combinations, in order.
    pub fn combination_names(&self) -> Vec<&str> {
        self.combinations.keys().map(String::as_str).collect()
    }

    /// The scene under the combination `name`: its keys merged over the scene file's (a table
    /// key by key, any other value replaced), then read and checked as a scene. An error names
    /// the combination.
    pub fn combination(&self, name: &str) -> Result<Scene, SceneError> {
        let overrides = self.combinations.get(name).ok_or_else(|| {
            self.invalid(format!(
                "no combination '{name}'; the scene has: {}",
                if self.combinations.is_empty() { "none".into() } else { self.combination_names().join(", ") }
            ))
        })?;
        let context = PathBuf::from(format!("{} [combinations.{name}]", self.source.display()));
        if let Some(key) = overrides.keys().find(|k| !OVERRIDABLE.contains(&k.as_str())) {
            return Err(SceneError::Invalid {
                path: context,
                message: format!(
                    "'{key}' cannot be overridden: a combination changes [boundary.*], [loads] and [uplift] only"
                ),
            });
        }
        let mut table = self.table.clone();
        merge(&mut table, overrides);
        let mut scene = Scene::from_table(&context, table)?;
        scene.source.clone_from(&self.source);
        Ok(scene)
    }
}

/// Merges `overrides` into `table`: tables key by key, any other value replaced.
fn merge(table: &mut toml::Table, overrides: &toml::Table) {
    for (key, value) in overrides {
        match (table.get_mut(key), value) {
            (Some(toml::Value::Table(inner)), toml::Value::Table(over)) => merge(inner, over),
            _ => {
                table.insert(key.clone(), value.clone());
            }
        }
    }
}
