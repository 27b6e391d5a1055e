//! Rust twins of `glsl/cwbvh.glsl`: the traversal of the compressed wide BVH
//! (`CompressedBvh`), operation for operation and in the same order, so that they visit the
//! same nodes and test the same triangles as the shader. Where the shader reads
//! `g_bvh_node_texels` and `g_traversal_triangle_texels`, the twins take the nodes and the
//! packed triangles (`packed_traversal_triangles`) as their first parameters. Change both
//! together.
//!
//! The traversal is Ylitie et al.'s (2017, section 4): the stack holds node groups (an
//! interior node's children that the ray entered and that are still to visit, as a bit mask
//! beside the node's inner mask) rather than single nodes; the leaves' triangles that the ray
//! entered form a triangle group tested before the next node. A node's children are visited
//! in the order of their slots, which the builder sorted by octant: xor-ing the slot with the
//! ray's octant makes the highest set bit the child nearest along the ray's direction.

use glam::Vec3;

use super::compressed::GpuCompressedBvhNode;
use super::traversal::bvh_inverse_direction;
use crate::contract::{BVH_SLAB_PADDING, CWBVH_STACK_SIZE, NO_HIT_T, PACKED_TRIANGLE_WORD_COUNT};
use crate::cpu::integrator::MeshHit;
use crate::cpu::workshop::ray_triangle_intersection;
use crate::scene::Triangle;

const STACK_SIZE: usize = CWBVH_STACK_SIZE as usize;
/// The node group's bits of the children still to visit (one per slot, xor the octant).
const NODE_HITS: u32 = 0xFF00_0000;
/// The triangle group's bits (one per triangle offset from the node's first triangle).
const TRIANGLE_HITS: u32 = 0x00FF_FFFF;

/// Twin of GLSL `shift_texels`: the four words that start at word `offset` (0 to 3) of the
/// eight words of texels `a` then `b`.
pub fn shift_texels(a: [u32; 4], b: [u32; 4], offset: u32) -> [u32; 4] {
    match offset {
        0 => a,
        1 => [a[1], a[2], a[3], b[0]],
        2 => [a[2], a[3], b[0], b[1]],
        _ => [a[3], b[0], b[1], b[2]],
    }
}

/// Twin of GLSL `get_packed_traversal_triangle`: triangle `index` of the packed traversal
/// triangles (`packed_traversal_triangles`), its positions bit for bit and zeros for the
/// members that `ray_triangle_intersection` does not read.
///
/// # Panics
/// If `index` is out of range.
pub fn get_packed_traversal_triangle(texels: &[[f32; 4]], index: u32) -> Triangle {
    let first_word = PACKED_TRIANGLE_WORD_COUNT * index;
    let texel = (first_word >> 2) as usize;
    let offset = first_word & 3;
    let fetch = |i: usize| texels[i].map(f32::to_bits);
    let (a, b, c) = (fetch(texel), fetch(texel + 1), fetch(texel + 2));
    // Words 0-3 start at `offset` in a, b; words 4-7 in b, c; word 8 is c[offset]
    let low = shift_texels(a, b, offset).map(f32::from_bits);
    let high = shift_texels(b, c, offset).map(f32::from_bits);
    let last = f32::from_bits(shift_texels(c, c, offset)[0]);
    Triangle {
        positions: [
            Vec3::new(low[0], low[1], low[2]),
            Vec3::new(low[3], high[0], high[1]),
            Vec3::new(high[2], high[3], last),
        ],
        normal: Vec3::ZERO,
        color: Vec3::ZERO,
        emission: Vec3::ZERO,
        double_sided: false,
    }
}

/// Twin of GLSL `cwbvh_octant_inverse`: 7 minus the ray's octant (bit 2: x, bit 1: y, bit 0:
/// z, set for a negative component; -0 counts as positive, as in `bvh_inverse_direction`),
/// which the builder's child order expects.
pub fn cwbvh_octant_inverse(ray_direction: Vec3) -> u32 {
    (if ray_direction.x < 0.0 { 0 } else { 4 })
        | (if ray_direction.y < 0.0 { 0 } else { 2 })
        | (if ray_direction.z < 0.0 { 0 } else { 1 })
}

/// Twin of GLSL `cwbvh_intersect_child`: the slab test of `bvh_ray_box_intersection` on the
/// dequantised box of child `slot` (0-7), in the node's grid (plane `q` at `t = q *
/// scaled_inverse + shifted_origin`), exit padded by `BVH_SLAB_PADDING`.
/// \param planes Per axis (x, y, z) the lower planes of slots 0-3, of 4-7, the upper planes
///        of slots 0-3, of 4-7, a byte per child (slot k: bits `8 (k & 3)` ..)
/// \param meta_words The children's meta bytes, slots 0-3 then 4-7, likewise
/// \return Its hit bits if entered (else 0): bit `24 + (slot ^ octant_inverse)` for an
///         interior child, the offsets of a leaf's triangles from the node's first triangle
pub fn cwbvh_intersect_child(
    slot: u32,
    planes: [[u32; 4]; 3],
    meta_words: [u32; 2],
    scaled_inverse: Vec3,
    shifted_origin: Vec3,
    octant_inverse: u32,
    t_max: f32,
) -> u32 {
    let half = (slot >> 2) as usize;
    let shift = 8 * (slot & 3);
    let plane = |axis: usize, upper: usize| {
        ((planes[axis][2 * upper + half] >> shift) & 255) as f32 * scaled_inverse[axis]
            + shifted_origin[axis]
    };
    let t_lower_x = plane(0, 0);
    let t_upper_x = plane(0, 1);
    let t_lower_y = plane(1, 0);
    let t_upper_y = plane(1, 1);
    let t_lower_z = plane(2, 0);
    let t_upper_z = plane(2, 1);
    let t_entry = t_lower_x
        .min(t_upper_x)
        .max(t_lower_y.min(t_upper_y))
        .max(t_lower_z.min(t_upper_z).max(0.0));
    let t_exit = t_lower_x
        .max(t_upper_x)
        .min(t_lower_y.max(t_upper_y))
        .min(t_lower_z.max(t_upper_z))
        * BVH_SLAB_PADDING;
    let meta = (meta_words[half] >> shift) & 255;
    // Interior children's meta is 24 + slot: bits 3 and 4 both set, never in a leaf's
    let inner = meta & (meta << 1) & 16 != 0;
    let child_bits = if inner { 1 } else { meta >> 5 };
    let bit_index = if inner {
        (meta & 31) ^ octant_inverse
    } else {
        meta & 31
    };
    if t_entry <= t_exit.min(t_max) {
        child_bits << bit_index
    } else {
        0
    }
}

/// Twin of GLSL `cwbvh_intersect_node`: which children of node `node_index` the ray enters
/// before `t_max` (`cwbvh_intersect_child` for slots 0-7).
/// \return The node group (x: the node's first interior child; y: bit `24 + (slot ^
///         octant_inverse)` for each interior child entered | the node's inner mask) and the
///         triangle group (x: the node's first triangle; y: the offsets from it of the
///         triangles of the leaves entered)
pub fn cwbvh_intersect_node(
    nodes: &[GpuCompressedBvhNode],
    node_index: u32,
    ray_origin: Vec3,
    inverse_direction: Vec3,
    octant_inverse: u32,
    t_max: f32,
) -> ([u32; 2], [u32; 2]) {
    let node = &nodes[node_index as usize];
    let scaled_inverse = node.scale() * inverse_direction;
    let shifted_origin = (Vec3::from(node.origin) - ray_origin) * inverse_direction;
    // Bytes `4 half ..` of an array of 8 bytes: a word of texels 1-4
    let word = |bytes: &[u8; 8], half: usize| {
        u32::from_le_bytes([
            bytes[4 * half],
            bytes[4 * half + 1],
            bytes[4 * half + 2],
            bytes[4 * half + 3],
        ])
    };
    // Texels 2-4 as the shader reads them: lower 0-3, lower 4-7, upper 0-3, upper 4-7
    let texel = |lower: &[u8; 8], upper: &[u8; 8]| {
        [
            word(lower, 0),
            word(lower, 1),
            word(upper, 0),
            word(upper, 1),
        ]
    };
    let planes = [
        texel(&node.lower_x, &node.upper_x),
        texel(&node.lower_y, &node.upper_y),
        texel(&node.lower_z, &node.upper_z),
    ];
    let meta_words = [word(&node.child_meta, 0), word(&node.child_meta, 1)];
    let mut hits = 0;
    for slot in 0..8 {
        hits |= cwbvh_intersect_child(
            slot,
            planes,
            meta_words,
            scaled_inverse,
            shifted_origin,
            octant_inverse,
            t_max,
        );
    }
    (
        [
            node.child_base,
            (hits & NODE_HITS) | u32::from(node.inner_mask()),
        ],
        [node.triangle_base, hits & TRIANGLE_HITS],
    )
}

/// Twin of GLSL `cwbvh_stack_entry`: a node group as the stack holds it, the index of the
/// node whose group it is (bits 8-31; `CompressedBvh` has fewer than `CWBVH_MAX_NODE_COUNT`
/// nodes) and the children still to visit (bits 0-7: bits 24-31 of `node_group[1]`).
pub fn cwbvh_stack_entry(group_node_index: u32, node_group: [u32; 2]) -> u32 {
    (group_node_index << 8) | (node_group[1] >> 24)
}

/// Twin of GLSL `cwbvh_node_group_of_entry`: the node group of a stack entry, its node's first
/// interior child and inner mask read again beside the children still to visit.
///
/// # Panics
/// If the entry's node is out of range.
pub fn cwbvh_node_group_of_entry(nodes: &[GpuCompressedBvhNode], entry: u32) -> [u32; 2] {
    let node = &nodes[(entry >> 8) as usize];
    [
        node.child_base,
        (entry << 24) | u32::from(node.inner_mask()),
    ]
}

/// The state of a compressed traversal: the node group and triangle group in hand and the
/// stack of node groups (GLSL: locals of `cwbvh_closest_hit` and `cwbvh_any_hit`).
struct Groups {
    /// x: the first interior child's node index; y: bits 24-31 the children still to visit
    /// (slot ^ octant), bits 0-7 the node's inner mask.
    node_group: [u32; 2],
    /// The node whose group `node_group` is (the root's group has none: it is never pushed).
    group_node_index: u32,
    /// x: the first triangle; y: bits 0-23 the triangles still to test (offsets from x).
    triangle_group: [u32; 2],
    /// Node groups as `cwbvh_stack_entry` packs them: one array, where the shader keeps the
    /// first `CWBVH_REGISTER_STACK_SIZE` in registers and the rest in shared memory
    /// (`CWBVH_PUSH`, `CWBVH_POP`: where an entry is kept is no maths).
    stack: [u32; STACK_SIZE],
    stack_size: usize,
}

impl Groups {
    fn new() -> Groups {
        Groups {
            // The root: node 0 as the only child, interior, of a node group at base 0
            node_group: [0, 0x8000_0000],
            group_node_index: 0,
            triangle_group: [0, 0],
            stack: [0; STACK_SIZE],
            stack_size: 0,
        }
    }

    /// The next triangle of the triangle group, lowest offset first (`None` when it is
    /// empty): the head of the GLSL traversals' triangle loop.
    fn next_triangle(&mut self) -> Option<u32> {
        if self.triangle_group[1] == 0 {
            return None;
        }
        let local = self.triangle_group[1].trailing_zeros();
        self.triangle_group[1] &= !(1u32 << local);
        Some(self.triangle_group[0] + local)
    }

    /// A node group with nodes left: the one in hand, else one popped from the stack
    /// (`false` when that is empty: the traversal ends).
    fn node_group_with_nodes(&mut self, nodes: &[GpuCompressedBvhNode]) -> bool {
        if self.node_group[1] & NODE_HITS == 0 {
            if self.stack_size == 0 {
                return false;
            }
            self.stack_size -= 1;
            self.group_node_index = self.stack[self.stack_size] >> 8;
            self.node_group = cwbvh_node_group_of_entry(nodes, self.stack[self.stack_size]);
        }
        true
    }

    /// Twin of GLSL `CWBVH_NEXT_NODE`: the next node of the node group in hand (which has
    /// nodes left), pushing what is left of the group; the node's group comes next (GLSL:
    /// `group_node_index = node_index` after the macro).
    fn next_node(&mut self, octant_inverse: u32) -> u32 {
        let hits_inner = self.node_group[1];
        let bit = 31 - hits_inner.leading_zeros();
        self.node_group[1] &= !(1u32 << bit);
        if self.node_group[1] & NODE_HITS != 0 && self.stack_size < STACK_SIZE {
            self.stack[self.stack_size] = cwbvh_stack_entry(self.group_node_index, self.node_group);
            self.stack_size += 1;
        }
        let slot = (bit - 24) ^ octant_inverse;
        let below = hits_inner & ((1u32 << slot) - 1);
        let node_index = self.node_group[0] + below.count_ones();
        self.group_node_index = node_index;
        node_index
    }
}

/// Twin of GLSL `cwbvh_step_bound`: most steps of one traversal, every node visited once,
/// every triangle tested once (their count from the packed triangles' texels, padding
/// included), and a pop for at most every node visit (a bound of the steps' loop, which
/// visits one node per step, and of the traversal's iterations as the kernel counts them).
pub fn cwbvh_step_bound(nodes: &[GpuCompressedBvhNode], packed_triangles: &[[f32; 4]]) -> usize {
    let triangle_count = 4 * packed_triangles.len() / PACKED_TRIANGLE_WORD_COUNT as usize;
    2 * nodes.len() + triangle_count + 1
}

/// Finds the closest triangle that a ray hits, twin of GLSL `cwbvh_closest_hit`: brute
/// force's triangle tests, children in octant order, nodes culled by the closest hit so far.
/// \param nodes The compressed BVH's nodes (the shader's `g_bvh_node_texels`)
/// \param packed_triangles The packed traversal triangles in leaf order
///        (`packed_traversal_triangles`, the shader's `g_traversal_triangle_texels`)
/// \param ray_origin, ray_direction The ray, world space
/// \return The closest hit (t, index into the reordered triangles), `None` iff no triangle
///         is hit at t < `NO_HIT_T`
///
/// # Panics
/// If the nodes index past `nodes` or `packed_triangles` (a tree built for other triangles).
pub fn cwbvh_closest_hit(
    nodes: &[GpuCompressedBvhNode],
    packed_triangles: &[[f32; 4]],
    ray_origin: Vec3,
    ray_direction: Vec3,
) -> Option<MeshHit> {
    let mut out_t = NO_HIT_T;
    let mut out_triangle_index = 0u32;
    let mut hit = false;
    if nodes.is_empty() {
        return None;
    }
    let inverse_direction = bvh_inverse_direction(ray_direction);
    let octant_inverse = cwbvh_octant_inverse(ray_direction);
    let mut groups = Groups::new();
    for _ in 0..cwbvh_step_bound(nodes, packed_triangles) {
        // The triangles of the leaves just entered, all before the next node
        while let Some(i) = groups.next_triangle() {
            let triangle = get_packed_traversal_triangle(packed_triangles, i);
            if let Some(t) = ray_triangle_intersection(ray_origin, ray_direction, &triangle) {
                if t < out_t {
                    out_t = t;
                    out_triangle_index = i;
                    hit = true;
                }
            }
        }
        if !groups.node_group_with_nodes(nodes) {
            break;
        }
        let index = groups.next_node(octant_inverse);
        (groups.node_group, groups.triangle_group) = cwbvh_intersect_node(
            nodes,
            index,
            ray_origin,
            inverse_direction,
            octant_inverse,
            out_t,
        );
    }
    hit.then_some(MeshHit {
        t: out_t,
        triangle_index: out_triangle_index as usize,
    })
}

/// Whether a ray hits any triangle at t < `t_max` (shadow rays), twin of GLSL
/// `cwbvh_any_hit`: the traversal of `cwbvh_closest_hit` with a fixed `t_max`, ending at the
/// first hit found.
/// \param nodes, packed_triangles As for `cwbvh_closest_hit`
/// \param ray_origin, ray_direction The ray, world space
/// \param t_max Hits at or beyond this ray parameter do not count
///
/// # Panics
/// If the nodes index past `nodes` or `packed_triangles`.
pub fn cwbvh_any_hit(
    nodes: &[GpuCompressedBvhNode],
    packed_triangles: &[[f32; 4]],
    ray_origin: Vec3,
    ray_direction: Vec3,
    t_max: f32,
) -> bool {
    if nodes.is_empty() {
        return false;
    }
    let inverse_direction = bvh_inverse_direction(ray_direction);
    let octant_inverse = cwbvh_octant_inverse(ray_direction);
    let mut groups = Groups::new();
    for _ in 0..cwbvh_step_bound(nodes, packed_triangles) {
        while let Some(i) = groups.next_triangle() {
            let triangle = get_packed_traversal_triangle(packed_triangles, i);
            if let Some(t) = ray_triangle_intersection(ray_origin, ray_direction, &triangle) {
                if t < t_max {
                    return true;
                }
            }
        }
        if !groups.node_group_with_nodes(nodes) {
            break;
        }
        let index = groups.next_node(octant_inverse);
        (groups.node_group, groups.triangle_group) = cwbvh_intersect_node(
            nodes,
            index,
            ray_origin,
            inverse_direction,
            octant_inverse,
            t_max,
        );
    }
    false
}
