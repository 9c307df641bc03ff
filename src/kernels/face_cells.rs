//! The contact search grid's bucket of every primary face (CPU twin of
//! `shaders/face_cells.wgsl`): the cell of the face's centre ([`face_centre`]) hashed with
//! its interface.

/// The bucket of grid cell `c` of the interface whose faces start at `salt`, in a table of
/// `mask + 1` buckets (the WGSL `cell_key`, in the same wrapping u32 arithmetic).
pub(crate) fn cell_key(c: [i32; 3], salt: u32, mask: u32) -> u32 {
    let h = (c[0] as u32).wrapping_mul(73856093)
        ^ (c[1] as u32).wrapping_mul(19349663)
        ^ (c[2] as u32).wrapping_mul(83492791)
        ^ salt.wrapping_mul(2654435761);
    h & mask
}

/// The grid cell of a point.
pub(crate) fn cell_of(x: [f64; 3], cell: f64) -> [i32; 3] {
    x.map(|c| (c / cell).floor() as i32)
}

/// `positions` are the current node positions; `face_first[f]` the first face of face f's
/// interface.
pub fn face_cells(
    positions: &[[f64; 3]],
    faces: &[[u32; 4]],
    face_first: &[u32],
    cell: f64,
    mask: u32,
) -> Vec<u32> {
    faces
        .iter()
        .zip(face_first)
        .map(|(f, &salt)| {
            let c = face_centre(f, |n| positions[n as usize]);
            cell_key(cell_of(c, cell), salt, mask)
        })
        .collect()
}

/// A face's box (lowest and highest corner coordinates), with `position` each node's
/// position: the narrow phase's first filter (the device's in f32).
pub fn face_box(f: &[u32; 4], position: impl Fn(u32) -> [f64; 3]) -> [[f64; 3]; 2] {
    let p = f.map(position);
    let fold = |a: usize, pick: fn(f64, f64) -> f64| p.iter().map(|y| y[a]).reduce(pick).unwrap();
    [
        std::array::from_fn(|a| fold(a, f64::min)),
        std::array::from_fn(|a| fold(a, f64::max)),
    ]
}

/// The mean of a face's four stored corners (inside a triangle, whose fourth slot repeats
/// its third, too; not its centroid), with `position` each node's position: the point the
/// grid sorts the face by, kept to measure how far it moves (`search_bounds`).
pub fn face_centre(f: &[u32; 4], position: impl Fn(u32) -> [f64; 3]) -> [f64; 3] {
    let p = f.map(position);
    std::array::from_fn(|a| 0.25 * (p[0][a] + p[1][a] + p[2][a] + p[3][a]))
}
