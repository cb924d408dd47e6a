//! Conversion of gmsh's current mesh into a [`Mesh`] of the plane or of space.

use super::{api, GmshError};
use crate::geometry::Point;
use crate::mesh::flat::flip_flat_cells;
use crate::mesh::{Mesh, PhysicalGroup};
use std::collections::HashMap;
use std::path::Path;

/// Reads the current mesh as [`Session::mesh`](super::Session::mesh) describes; `source`
/// names the file in errors. On a mesh gmsh has just made (`meshed`), the cells of zero area
/// its Delaunay-based algorithms leave along straight boundaries are flipped away
/// ([`flip_flat_cells`]); any other cell of zero area is an error.
pub(super) fn mesh(source: &Path, meshed: bool) -> Result<Mesh, GmshError> {
    let mut mesh: Mesh = simplices(source, || GmshError::NoTriangles { path: source.into() })?;
    if meshed {
        flip_flat_cells(&mut mesh).map_err(|[x, y]| GmshError::Degenerate { path: source.into(), x, y })?;
    }
    if let Some(c) = (0..mesh.n_cells()).find(|&c| mesh.cell_area(c) == 0.0) {
        let [x, y] = mesh.points[mesh.cell(c)[0]];
        return Err(GmshError::Degenerate { path: source.into(), x, y });
    }
    mesh.orient_counter_clockwise();
    if let Some(edge) = folded_edge(&mesh) {
        return Err(GmshError::Folded { path: source.into(), edge });
    }
    Ok(mesh)
}

/// Reads the current mesh of a model with volumes: its tetrahedra and the triangles of its
/// physical surfaces, the cells positively oriented. A tetrahedron of zero volume is an
/// error.
pub(super) fn solid(source: &Path) -> Result<Mesh<3>, GmshError> {
    let mut mesh: Mesh<3> = simplices(source, || GmshError::NoTetrahedra { path: source.into() })?;
    if let Some(c) = (0..mesh.n_cells()).find(|&c| mesh.cell_volume(c) == 0.0) {
        let x = mesh.points[mesh.cell(c)[0]];
        return Err(GmshError::FlatTetrahedron { path: source.into(), x });
    }
    mesh.orient_positively();
    Ok(mesh)
}

/// The cells of dimension D (`none` if there is none), the facets of the physical groups of
/// dimension D − 1 and the groups, as gmsh lists them.
fn simplices<const D: usize>(source: &Path, none: impl Fn() -> GmshError) -> Result<Mesh<D>, GmshError> {
    let cells = elements(D as i32, true, source)?;
    let order = cells.order.ok_or_else(none)?;
    let facets = elements(D as i32 - 1, false, source)?;
    if facets.order.is_some_and(|o| o != order) {
        return Err(GmshError::MixedOrder { path: source.into() });
    }
    let groups = groups(D as i32)?;
    let mut numbering = Numbering::<D>::new()?;
    let cell_nodes = cells.nodes.iter().map(|&tag| numbering.add(tag)).collect::<Result<_, _>>()?;
    let facet_nodes = numbering.facets(&facets, &groups, source)?;
    Ok(Mesh {
        points: numbering.points,
        order,
        cell_nodes,
        cell_tags: cells.tags,
        facet_nodes,
        facet_tags: facets.tags,
        groups,
    })
}

/// An edge where counter-clockwise cells overlap: shared by more than two cells, or by two
/// that run along it in the same direction (so lie on the same side of it).
fn folded_edge(mesh: &Mesh) -> Option<[Point; 2]> {
    let edges = mesh.cell_type().edges();
    let mut directed: Vec<([usize; 2], bool)> = (0..mesh.n_cells())
        .flat_map(|c| {
            let v = &mesh.cell(c)[..3];
            edges.iter().map(move |&[i, j]| (v[i], v[j]))
        })
        .map(|(a, b)| ([a.min(b), a.max(b)], a < b))
        .collect();
    directed.sort_unstable();
    let folded = directed.chunk_by(|x, y| x.0 == y.0).find(|g| g.len() > 2 || (g.len() == 2 && g[0].1 == g[1].1))?;
    let [a, b] = folded[0].0;
    Some([mesh.points[a], mesh.points[b]])
}

/// Elements of one dimension, with gmsh's node tags.
#[derive(Default)]
struct Elements {
    order: Option<usize>,
    /// Nodes per element.
    stride: usize,
    /// Node tags, element after element.
    nodes: Vec<usize>,
    /// Physical tag of each element.
    tags: Vec<i32>,
}

/// The simplices of every entity of dimension `dim` (`cells`) or of every physical group of
/// that dimension (facets): tetrahedra (dim 3), triangles (2) or segments (1).
fn elements(dim: i32, cells: bool, source: &Path) -> Result<Elements, GmshError> {
    let mut elements = Elements::default();
    for (entity, tag) in tagged_entities(dim, cells)? {
        for &element_type in api::element_types(dim, entity)?.as_slice() {
            let (order, n) = match (dim, element_type) {
                (3, 4) => (1, 4),
                (3, 11) => (2, 10),
                (2, 2) => (1, 3),
                (2, 9) => (2, 6),
                (1, 1) => (1, 2),
                (1, 8) => (2, 3),
                _ => return Err(unsupported(element_type, source)),
            };
            if *elements.order.get_or_insert(order) != order {
                return Err(GmshError::MixedOrder { path: source.into() });
            }
            elements.stride = n;
            let nodes = api::element_nodes(element_type, entity)?;
            elements.nodes.extend_from_slice(nodes.as_slice());
            let count = nodes.as_slice().len() / n;
            elements.tags.extend(std::iter::repeat_n(tag, count));
        }
    }
    Ok(elements)
}

/// (entity, physical tag) pairs of dimension `dim`: of `cells`, every entity with its first
/// group (0 if none); of facets, every (entity, group) pair of the physical groups, by group,
/// each group's entities in model order (as gmsh lists a group's entities). The groups of each
/// entity are asked for, not the entities of each group, which gmsh finds by a pass over every
/// group.
fn tagged_entities(dim: i32, cells: bool) -> Result<Vec<(i32, i32)>, GmshError> {
    let mut pairs = Vec::new();
    if cells {
        for (_, entity) in api::entities(dim)? {
            let groups = api::entity_groups(dim, entity)?;
            pairs.push((entity, groups.as_slice().first().copied().unwrap_or(0)));
        }
    } else {
        let mut entities: HashMap<i32, Vec<i32>> = HashMap::new();
        for (_, entity) in api::entities(dim)? {
            for &group in api::entity_groups(dim, entity)?.as_slice() {
                let listed = entities.entry(group).or_default();
                if listed.last() != Some(&entity) {
                    listed.push(entity);
                }
            }
        }
        for (_, group) in api::physical_groups(dim)? {
            pairs.extend(entities.remove(&group).unwrap_or_default().into_iter().map(|entity| (entity, group)));
        }
    }
    Ok(pairs)
}

fn unsupported(element_type: i32, source: &Path) -> GmshError {
    match api::element_name(element_type) {
        Ok(element) => GmshError::Unsupported { path: source.into(), element },
        Err(e) => e,
    }
}

/// Physical groups of dimension `d` − 1 and `d` with their names.
fn groups(d: i32) -> Result<Vec<PhysicalGroup>, GmshError> {
    api::physical_groups(-1)?
        .into_iter()
        .filter(|&(dim, _)| dim == d - 1 || dim == d)
        .map(|(dim, tag)| Ok(PhysicalGroup { dim: dim as u8, tag, name: api::physical_name(dim, tag)? }))
        .collect()
}

/// Compact node numbering in order of first use.
struct Numbering<const D: usize> {
    /// The first D coordinates of every gmsh node, by tag.
    xy: HashMap<usize, [f64; D]>,
    /// gmsh tag → new index.
    index: HashMap<usize, usize>,
    points: Vec<[f64; D]>,
}

impl<const D: usize> Numbering<D> {
    fn new() -> Result<Numbering<D>, GmshError> {
        let (tags, coords) = api::nodes()?;
        let xy = tags
            .as_slice()
            .iter()
            .zip(coords.as_slice().chunks_exact(3))
            .map(|(&tag, c)| (tag, std::array::from_fn(|r| c[r])))
            .collect();
        Ok(Numbering { xy, index: HashMap::new(), points: Vec::new() })
    }

    /// Index of node `tag`, numbering it if new.
    fn add(&mut self, tag: usize) -> Result<usize, GmshError> {
        if let Some(&i) = self.index.get(&tag) {
            return Ok(i);
        }
        let xy = *self.xy.get(&tag).ok_or_else(|| GmshError::Call {
            call: "gmshModelMeshGetNodes",
            message: format!("node {tag} of an element is missing"),
        })?;
        self.points.push(xy);
        self.index.insert(tag, self.points.len() - 1);
        Ok(self.points.len() - 1)
    }

    /// Facet connectivity in the numbering of the cells.
    fn facets(&self, facets: &Elements, groups: &[PhysicalGroup], source: &Path) -> Result<Vec<usize>, GmshError> {
        let n = facets.stride.max(1);
        let mut nodes = Vec::with_capacity(facets.nodes.len());
        for (facet, &tag) in facets.nodes.chunks(n).zip(&facets.tags) {
            for node in facet {
                let index = self.index.get(node).ok_or_else(|| detached::<D>(tag, groups, source))?;
                nodes.push(*index);
            }
        }
        Ok(nodes)
    }
}

fn detached<const D: usize>(tag: i32, groups: &[PhysicalGroup], source: &Path) -> GmshError {
    let group = groups
        .iter()
        .find(|g| g.dim as usize == D - 1 && g.tag == tag && !g.name.is_empty())
        .map_or_else(|| tag.to_string(), |g| g.name.clone());
    GmshError::DetachedCurve { path: source.into(), group, what: ["curve", "surface"][D - 2] }
}
