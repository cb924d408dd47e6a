//! The flags that override scene keys. Each command lists its flags in one table of
//! [`Setting`]s: the flag, the key it overrides, and how it writes the scene when given.
//! [`write`] writes the given ones, and [`Given`] checks the scene with them, an error that
//! names a key blamed on the flag that set it.

use crate::scene::{Scene, SceneError};
use anyhow::Result;

/// A write of a flag's value into the scene.
type Write<'a> = Box<dyn FnOnce(&mut Scene) + 'a>;

/// A flag that overrides the scene key `key`, with the write it makes if given.
pub struct Setting<'a> {
    flag: &'static str,
    key: &'static str,
    write: Option<Write<'a>>,
}

impl<'a> Setting<'a> {
    /// The flag `flag` with the value `value` (None: not given), written by `write`.
    pub fn value<T: 'a>(flag: &'static str, key: &'static str, value: Option<T>, write: fn(&mut Scene, T)) -> Self {
        let write = value.map(|v| Box::new(move |scene: &mut Scene| write(scene, v)) as Write);
        Setting { flag, key, write }
    }

    /// The switch `flag`, given when `on`, written by `write`.
    pub fn switch(flag: &'static str, key: &'static str, on: bool, write: fn(&mut Scene)) -> Self {
        let write = on.then(|| Box::new(write) as Write);
        Setting { flag, key, write }
    }
}

/// The flags given on the command line, each with the key it overrode.
pub struct Given(Vec<(&'static str, &'static str)>);

impl Given {
    /// The flags given among `flags`.
    pub fn among<'f>(&'f self, flags: &'f [&str]) -> impl Iterator<Item = &'static str> + 'f {
        self.0.iter().map(|(flag, _)| *flag).filter(|flag| flags.contains(flag))
    }

    /// Validates `scene`, an error blamed on the flag that set its key.
    pub fn validate(&self, scene: &Scene) -> Result<()> {
        self.blame(scene.validate())
    }

    /// The error of a check of the scene, blamed on the flag that overrides the key it names,
    /// if one does.
    pub fn blame(&self, checked: Result<(), SceneError>) -> Result<()> {
        let Err(e) = checked else { return Ok(()) };
        let SceneError::Invalid { message, .. } = &e else { return Err(e.into()) };
        match self.0.iter().find(|(_, key)| message.starts_with(&format!("{key} "))) {
            Some((flag, key)) => {
                anyhow::bail!("{flag}{} (given on the command line, where it overrides {key})", &message[key.len()..])
            }
            None => Err(e.into()),
        }
    }
}

/// Writes the given settings of `table` into `scene`; returns the flags given.
pub fn write(scene: &mut Scene, table: Vec<Setting>) -> Given {
    let mut given = Vec::new();
    for Setting { flag, key, write } in table {
        if let Some(write) = write {
            write(scene);
            given.push((flag, key));
        }
    }
    Given(given)
}
