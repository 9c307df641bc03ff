// The constraints of the explicit step's contact iteration, one pair per invocation (twin:
// `kernels::contact_constraints`), as the host path gathers them (`integrate::explicit`):
// a surface pair takes its query's contact point (face, shape functions, normal, gap at u_n)
// and is in reach if a face was found with g >= -margin; a plane pair takes the plane's
// normal and gap and is in reach if g >= -4 dt |v*| (four steps of its node's motion).
// The slip at v_{n-1/2} = v* - dt a_n is kept for the friction work. The impulses and the
// compliance start at zero. keys[p]: the pair's face for the bucket sort by face (an
// in-reach surface pair), otherwise params.aux (one bucket past the faces).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> grid: SearchGrid;
@group(0) @binding(3) var<storage, read> reference: array<Split3>;
@group(0) @binding(4) var<storage, read> displacement: array<Split3>;
@group(0) @binding(5) var<storage, read> velocity: array<f32>;
@group(0) @binding(6) var<storage, read> acceleration: array<f32>;
@group(0) @binding(7) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(8) var<storage, read> points: array<ContactPoint>;
@group(0) @binding(9) var<storage, read> faces: array<Quad>;
@group(0) @binding(10) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(11) var<storage, read_write> keys: array<u32>;

fn load_v(n: u32) -> vec3<f32> {
    return vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
}

fn load_a(n: u32) -> vec3<f32> {
    return vec3<f32>(acceleration[3u * n], acceleration[3u * n + 1u], acceleration[3u * n + 2u]);
}

@compute @workgroup_size(64)
fn contact_constraints(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = item_index(gid, params);
    if (p >= params.count) {
        return;
    }
    let pair = pairs[p];
    let n = pair.node;
    var c: Constraint;
    c.face = array<u32, 4>(NO_FACE, NO_FACE, NO_FACE, NO_FACE);
    c.weights = array<f32, 4>(0.0, 0.0, 0.0, 0.0);
    c.compliance = 0.0;
    c.jn = 0.0;
    c.jt = array<f32, 3>(0.0, 0.0, 0.0);
    var nrm = vec3<f32>(0.0);
    var gap = 0.0;
    var reach = false;
    var key = params.aux;
    let vn = load_v(n);
    // v_{n-1/2} of the relative motion: v* - dt a_n
    var rel_before = vn - step.dt * load_a(n);
    if (pair.query != NO_FACE) {
        let pt = points[pair.query];
        if (pt.face != NO_FACE) {
            let w = quad_shape(vec2<f32>(pt.xi[0], pt.xi[1]));
            let f = faces[pt.face];
            nrm = vec3<f32>(pt.normal[0], pt.normal[1], pt.normal[2]);
            gap = pt.gap;
            reach = gap >= -max(grid.margin, 1e-30);
            if (reach) {
                c.face = f.nodes;
                c.weights = array<f32, 4>(w.x, w.y, w.z, w.w);
                key = pt.face;
                for (var k = 0u; k < 4u; k++) {
                    let m = f.nodes[k];
                    rel_before -= c.weights[k] * (load_v(m) - step.dt * load_a(m));
                }
            }
        }
    } else {
        nrm = vec3<f32>(pair.normal[0], pair.normal[1], pair.normal[2]);
        let x = split_difference(reference[n], pair.point) + vec3<f32>(
            displacement[n].hi[0] + displacement[n].lo[0],
            displacement[n].hi[1] + displacement[n].lo[1],
            displacement[n].hi[2] + displacement[n].lo[2],
        );
        gap = -dot(x, nrm);
        reach = gap >= -4.0 * step.dt * length(vn);
    }
    c.normal = array<f32, 3>(nrm.x, nrm.y, nrm.z);
    c.gap = gap;
    let slip = rel_before - dot(rel_before, nrm) * nrm;
    c.slip = array<f32, 3>(slip.x, slip.y, slip.z);
    c.in_reach = select(0u, 1u, reach);
    constraints[p] = c;
    keys[p] = key;
}
