// The dam of Scene A on the rock block of Scene B (plane strain, SI units): the geometry of
// scene_b.geo, whose dam-rock interface has two physical curves, "joint" (0 <= x <= 32 m)
// and "bonded" (32 <= x <= 40 m). dam_on_rock.toml makes "joint" a contact joint between
// the two meshed bodies; gmsh meshes the interface conformingly and damfem splits its nodes.
Include "scene_b.geo";
