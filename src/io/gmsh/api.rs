//! Safe wrappers around the gmsh C calls: the only `unsafe` code of the crate.
//!
//! Callers must hold the session lock (see [`super::Session`]): gmsh's state is global.
//! Every call goes through [`check`]; every array gmsh allocates is owned by a [`GmshVec`].

use super::{ffi, GmshError};
use std::ffi::{c_char, c_int, CStr, CString};
use std::ptr;

/// An array allocated by gmsh, released with `gmshFree` when dropped.
pub(super) struct GmshVec<T> {
    ptr: *mut T,
    len: usize,
}

impl<T> GmshVec<T> {
    fn new() -> Self {
        GmshVec { ptr: ptr::null_mut(), len: 0 }
    }

    pub(super) fn as_slice(&self) -> &[T] {
        if self.ptr.is_null() {
            return &[];
        }
        // SAFETY: gmsh returned `len` initialised elements at `ptr`, owned by `self`.
        unsafe { std::slice::from_raw_parts(self.ptr, self.len) }
    }
}

impl<T> Drop for GmshVec<T> {
    fn drop(&mut self) {
        if !self.ptr.is_null() {
            // SAFETY: `ptr` was allocated by gmsh and is freed exactly once.
            unsafe { ffi::gmshFree(self.ptr.cast()) }
        }
    }
}

/// Turns a non-zero `ierr` of the C call `call` into [`GmshError::Call`] with gmsh's last error.
pub(super) fn check(ierr: c_int, call: &'static str) -> Result<(), GmshError> {
    if ierr == 0 {
        return Ok(());
    }
    let mut message = ptr::null_mut();
    let mut ignored = 0;
    // SAFETY: valid out-pointers; the returned string is taken over by `take_string`.
    unsafe { ffi::gmshLoggerGetLastError(&mut message, &mut ignored) };
    let message = take_string(message);
    Err(GmshError::Call { call, message: if message.is_empty() { "gmsh gave no message".into() } else { message } })
}

/// Runs one C call with a fresh `ierr` and checks it.
fn call<R>(name: &'static str, f: impl FnOnce(*mut c_int) -> R) -> Result<R, GmshError> {
    let mut ierr = 0;
    let result = f(&mut ierr);
    check(ierr, name).map(|()| result)
}

/// Copies a string allocated by gmsh and frees it.
fn take_string(p: *mut c_char) -> String {
    if p.is_null() {
        return String::new();
    }
    // SAFETY: gmsh returns NUL-terminated strings that the caller must free.
    unsafe {
        let s = CStr::from_ptr(p).to_string_lossy().into_owned();
        ffi::gmshFree(p.cast());
        s
    }
}

fn c_string(s: &str) -> CString {
    CString::new(s).expect("gmsh option names contain no NUL byte")
}

/// Schedules SIGALRM for this process in `seconds` (0: cancels the pending one).
pub(super) fn alarm(seconds: u32) {
    // SAFETY: alarm only sets the process's alarm clock.
    unsafe { libc::alarm(seconds) };
}

pub(super) fn initialize() -> Result<(), GmshError> {
    // SAFETY: no arguments are passed; called once, under the session lock.
    call("gmshInitialize", |e| unsafe { ffi::gmshInitialize(0, ptr::null_mut(), 0, e) })
}

pub(super) fn clear() -> Result<(), GmshError> {
    // SAFETY: plain call with a valid `ierr`.
    call("gmshClear", |e| unsafe { ffi::gmshClear(e) })
}

pub(super) fn open(path: &CStr) -> Result<(), GmshError> {
    // SAFETY: `path` is NUL-terminated and outlives the call.
    call("gmshOpen", |e| unsafe { ffi::gmshOpen(path.as_ptr(), e) })
}

pub(super) fn write(path: &CStr) -> Result<(), GmshError> {
    // SAFETY: `path` is NUL-terminated and outlives the call.
    call("gmshWrite", |e| unsafe { ffi::gmshWrite(path.as_ptr(), e) })
}

pub(super) fn generate(dim: c_int) -> Result<(), GmshError> {
    // SAFETY: plain call with a valid `ierr`.
    call("gmshModelMeshGenerate", |e| unsafe { ffi::gmshModelMeshGenerate(dim, e) })
}

pub(super) fn set_number(name: &str, value: f64) -> Result<(), GmshError> {
    let name = c_string(name);
    // SAFETY: `name` is NUL-terminated and outlives the call.
    call("gmshOptionSetNumber", |e| unsafe { ffi::gmshOptionSetNumber(name.as_ptr(), value, e) })
}

pub(super) fn get_number(name: &str) -> Result<f64, GmshError> {
    let name = c_string(name);
    let mut value = 0.0;
    // SAFETY: `name` is NUL-terminated; `value` is a valid out-pointer.
    call("gmshOptionGetNumber", |e| unsafe { ffi::gmshOptionGetNumber(name.as_ptr(), &mut value, e) })?;
    Ok(value)
}

/// Starts gmsh's message logger afresh, forgetting the messages of earlier sessions.
pub(super) fn restart_logger() -> Result<(), GmshError> {
    // SAFETY: plain calls with a valid `ierr`; stopping a stopped logger only warns.
    call("gmshLoggerStop", |e| unsafe { ffi::gmshLoggerStop(e) })?;
    call("gmshLoggerStart", |e| unsafe { ffi::gmshLoggerStart(e) })
}

/// Every message logged since the logger started, as "Error: ...", "Warning: ...", etc.
pub(super) fn logged() -> Result<Vec<String>, GmshError> {
    let mut log = GmshVec::<*mut c_char>::new();
    // SAFETY: valid out-pointers; the array and each string are freed below.
    call("gmshLoggerGet", |e| unsafe { ffi::gmshLoggerGet(&mut log.ptr, &mut log.len, e) })?;
    Ok(log.as_slice().iter().map(|&s| take_string(s)).collect())
}

/// (dim, tag) pairs from a flat gmsh `dimTags` array.
fn pairs(v: GmshVec<c_int>) -> Vec<(i32, i32)> {
    v.as_slice().chunks_exact(2).map(|p| (p[0], p[1])).collect()
}

/// (dim, tag) of the model entities of dimension `dim`.
pub(super) fn entities(dim: c_int) -> Result<Vec<(i32, i32)>, GmshError> {
    let mut v = GmshVec::new();
    // SAFETY: valid out-pointers, owned by `v`.
    call("gmshModelGetEntities", |e| unsafe { ffi::gmshModelGetEntities(&mut v.ptr, &mut v.len, dim, e) })?;
    Ok(pairs(v))
}

/// (dim, tag) of the physical groups of dimension `dim` (-1: all).
pub(super) fn physical_groups(dim: c_int) -> Result<Vec<(i32, i32)>, GmshError> {
    let mut v = GmshVec::new();
    // SAFETY: valid out-pointers, owned by `v`.
    call("gmshModelGetPhysicalGroups", |e| unsafe { ffi::gmshModelGetPhysicalGroups(&mut v.ptr, &mut v.len, dim, e) })?;
    Ok(pairs(v))
}

/// Name of a physical group ("" if unnamed).
pub(super) fn physical_name(dim: c_int, tag: c_int) -> Result<String, GmshError> {
    let mut name = ptr::null_mut();
    // SAFETY: valid out-pointer; the string is taken over by `take_string`.
    call("gmshModelGetPhysicalName", |e| unsafe { ffi::gmshModelGetPhysicalName(dim, tag, &mut name, e) })?;
    Ok(take_string(name))
}

/// Tags of the entities of a physical group.
pub(super) fn group_entities(dim: c_int, tag: c_int) -> Result<GmshVec<c_int>, GmshError> {
    let mut v = GmshVec::new();
    // SAFETY: valid out-pointers, owned by `v`.
    call("gmshModelGetEntitiesForPhysicalGroup", |e| unsafe {
        ffi::gmshModelGetEntitiesForPhysicalGroup(dim, tag, &mut v.ptr, &mut v.len, e)
    })?;
    Ok(v)
}

/// Tags of the physical groups an entity belongs to.
pub(super) fn entity_groups(dim: c_int, tag: c_int) -> Result<GmshVec<c_int>, GmshError> {
    let mut v = GmshVec::new();
    // SAFETY: valid out-pointers, owned by `v`.
    call("gmshModelGetPhysicalGroupsForEntity", |e| unsafe {
        ffi::gmshModelGetPhysicalGroupsForEntity(dim, tag, &mut v.ptr, &mut v.len, e)
    })?;
    Ok(v)
}

/// gmsh element types present on an entity.
pub(super) fn element_types(dim: c_int, tag: c_int) -> Result<GmshVec<c_int>, GmshError> {
    let mut v = GmshVec::new();
    // SAFETY: valid out-pointers, owned by `v`.
    call("gmshModelMeshGetElementTypes", |e| unsafe {
        ffi::gmshModelMeshGetElementTypes(&mut v.ptr, &mut v.len, dim, tag, e)
    })?;
    Ok(v)
}

/// gmsh's name of an element type, e.g. "Quadrilateral 4".
pub(super) fn element_name(element_type: c_int) -> Result<String, GmshError> {
    let mut name = ptr::null_mut();
    let (mut dim, mut order, mut nodes, mut primary) = (0, 0, 0, 0);
    let mut coords = GmshVec::<f64>::new();
    // SAFETY: valid out-pointers; `name` and `coords` are freed by their owners.
    call("gmshModelMeshGetElementProperties", |e| unsafe {
        ffi::gmshModelMeshGetElementProperties(
            element_type,
            &mut name,
            &mut dim,
            &mut order,
            &mut nodes,
            &mut coords.ptr,
            &mut coords.len,
            &mut primary,
            e,
        )
    })?;
    Ok(take_string(name))
}

/// Node tags of the elements of type `element_type` on entity `tag`, element after element.
pub(super) fn element_nodes(element_type: c_int, tag: c_int) -> Result<GmshVec<usize>, GmshError> {
    let mut elements = GmshVec::<usize>::new();
    let mut nodes = GmshVec::new();
    // SAFETY: valid out-pointers, owned by `elements` and `nodes`; one task of one.
    call("gmshModelMeshGetElementsByType", |e| unsafe {
        ffi::gmshModelMeshGetElementsByType(
            element_type,
            &mut elements.ptr,
            &mut elements.len,
            &mut nodes.ptr,
            &mut nodes.len,
            tag,
            0,
            1,
            e,
        )
    })?;
    Ok(nodes)
}

/// Tags and (x, y, z) coordinates of every mesh node.
pub(super) fn nodes() -> Result<(GmshVec<usize>, GmshVec<f64>), GmshError> {
    let mut tags = GmshVec::new();
    let mut coords = GmshVec::new();
    let mut parametric = GmshVec::<f64>::new();
    // SAFETY: valid out-pointers, owned by the three vectors.
    call("gmshModelMeshGetNodes", |e| unsafe {
        ffi::gmshModelMeshGetNodes(
            &mut tags.ptr,
            &mut tags.len,
            &mut coords.ptr,
            &mut coords.len,
            &mut parametric.ptr,
            &mut parametric.len,
            -1,
            -1,
            0,
            0,
            e,
        )
    })?;
    Ok((tags, coords))
}

/// Adds an empty post-processing view called `name`; returns its tag.
pub(super) fn view_add(name: &str) -> Result<c_int, GmshError> {
    let name = c_string(name);
    // SAFETY: `name` is NUL-terminated and outlives the call; tag -1 lets gmsh choose.
    call("gmshViewAdd", |e| unsafe { ffi::gmshViewAdd(name.as_ptr(), -1, e) })
}

/// Adds `count` list-based elements of type `data_type` (e.g. "ST": scalar triangles, each as
/// x1 x2 x3 y1 y2 y3 z1 z2 z3 v1 v2 v3) to view `view`.
pub(super) fn view_add_list_data(view: c_int, data_type: &str, count: usize, data: &[f64]) -> Result<(), GmshError> {
    let data_type = c_string(data_type);
    let count = c_int::try_from(count).map_err(|_| GmshError::Call {
        call: "gmshViewAddListData",
        message: format!("{count} elements are too many"),
    })?;
    // SAFETY: the pointers are valid for the call; gmsh copies `data` without writing to it
    // (the C header lacks `const`).
    call("gmshViewAddListData", |e| unsafe {
        ffi::gmshViewAddListData(view, data_type.as_ptr(), count, data.as_ptr().cast_mut(), data.len(), e)
    })
}

/// Adds a mesh size field of type `kind` (e.g. "PostView"); returns its tag.
pub(super) fn field_add(kind: &str) -> Result<c_int, GmshError> {
    let kind = c_string(kind);
    // SAFETY: `kind` is NUL-terminated and outlives the call; tag -1 lets gmsh choose.
    call("gmshModelMeshFieldAdd", |e| unsafe { ffi::gmshModelMeshFieldAdd(kind.as_ptr(), -1, e) })
}

/// Sets the numerical option `option` of field `field`.
pub(super) fn field_set_number(field: c_int, option: &str, value: f64) -> Result<(), GmshError> {
    let option = c_string(option);
    // SAFETY: `option` is NUL-terminated and outlives the call.
    call("gmshModelMeshFieldSetNumber", |e| unsafe {
        ffi::gmshModelMeshFieldSetNumber(field, option.as_ptr(), value, e)
    })
}

/// Sets the numerical list option `option` of field `field`.
pub(super) fn field_set_numbers(field: c_int, option: &str, values: &[f64]) -> Result<(), GmshError> {
    let option = c_string(option);
    // SAFETY: `option` is NUL-terminated and `values` valid for `values.len()` reads; gmsh copies both.
    call("gmshModelMeshFieldSetNumbers", |e| unsafe {
        ffi::gmshModelMeshFieldSetNumbers(field, option.as_ptr(), values.as_ptr().cast_mut(), values.len(), e)
    })
}

/// Tags of the entities of dimension `dim` + 1 adjacent to the entity (`dim`, `tag`).
pub(super) fn upward(dim: c_int, tag: c_int) -> Result<Vec<i32>, GmshError> {
    let (mut up, mut down) = (GmshVec::new(), GmshVec::<c_int>::new());
    // SAFETY: valid out-pointers, owned by `up` and `down`.
    call("gmshModelGetAdjacencies", |e| unsafe {
        ffi::gmshModelGetAdjacencies(dim, tag, &mut up.ptr, &mut up.len, &mut down.ptr, &mut down.len, e)
    })?;
    Ok(up.as_slice().to_vec())
}

/// Makes field `field` the background mesh size field, replacing any other.
pub(super) fn field_set_background(field: c_int) -> Result<(), GmshError> {
    // SAFETY: plain call with a valid `ierr`.
    call("gmshModelMeshFieldSetAsBackgroundMesh", |e| unsafe { ffi::gmshModelMeshFieldSetAsBackgroundMesh(field, e) })
}

/// Bounding box [xmin, ymin, zmin, xmax, ymax, zmax] of the whole model.
pub(super) fn bounding_box() -> Result<[f64; 6], GmshError> {
    let mut b = [0.0; 6];
    let [x0, y0, z0, x1, y1, z1] = &mut b;
    // SAFETY: six valid out-pointers.
    call("gmshModelGetBoundingBox", |e| unsafe { ffi::gmshModelGetBoundingBox(-1, -1, x0, y0, z0, x1, y1, z1, e) })?;
    Ok(b)
}

/// Removes the mesh of the whole model, keeping its geometry.
pub(super) fn clear_mesh() -> Result<(), GmshError> {
    // SAFETY: an empty dimTags array clears the whole mesh.
    call("gmshModelMeshClear", |e| unsafe { ffi::gmshModelMeshClear(ptr::null_mut(), 0, e) })
}
