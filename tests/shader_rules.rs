//! The rules every per-step WGSL kernel keeps so that it runs from registers on GPU hardware,
//! checked on naga's IR of each kernel (so any machine catches a regression, without a GPU):
//!
//! - no function-scope variable whose type holds an array (`var x: array<vec3<f32>, 8>`, or a
//!   struct with an array member);
//! - no function argument or result whose type holds an array;
//! - no dynamic index into an array *value* (`let h = hexes[e]; h.nodes[k]` with a loop
//!   variable k, or a `const` array indexed by one): naga spills such a value into a
//!   function-scope variable to index it.
//!
//! Function-scope arrays indexed by a variable live in per-thread local memory on NVIDIA and
//! AMD GPUs (each access goes through the cache hierarchy); software adapters hide it. The
//! same maths with constant indices ran 9-20x faster on an H100. Indexing a storage or
//! workgroup buffer through its pointer is not affected and stays allowed.
//!
//! The rules cover the functions reachable from each kernel's entry point. Kernels that run
//! once per run, at setup, are listed in [`SETUP_KERNELS`] and exempt.

use impact::gpu::shaders;
use naga::{Block, Expression, Function, Handle, Module, Statement, TypeInner};

/// Kernels that run once per run (not every step), with the reason.
const SETUP_KERNELS: [(&str, &str); 1] = [(
    "stable_step",
    "the critical time step of every element, computed once before the first step",
)];

fn parse(name: &str, source: &str) -> (Module, naga::valid::ModuleInfo) {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    (module, info)
}

/// Whether a type is, or holds, an array.
fn holds_array(module: &Module, ty: Handle<naga::Type>) -> bool {
    match &module.types[ty].inner {
        TypeInner::Array { .. } | TypeInner::BindingArray { .. } => true,
        TypeInner::Struct { members, .. } => members.iter().any(|m| holds_array(module, m.ty)),
        _ => false,
    }
}

/// The functions a block calls.
fn calls(block: &Block, out: &mut Vec<Handle<Function>>) {
    for s in block.iter() {
        match s {
            Statement::Call { function, .. } => out.push(*function),
            Statement::Block(b) => calls(b, out),
            Statement::If { accept, reject, .. } => {
                calls(accept, out);
                calls(reject, out);
            }
            Statement::Switch { cases, .. } => cases.iter().for_each(|c| calls(&c.body, out)),
            Statement::Loop {
                body, continuing, ..
            } => {
                calls(body, out);
                calls(continuing, out);
            }
            _ => {}
        }
    }
}

/// The breaches of the rules in one function (`info`: its analysis, for expression types).
fn breaches(
    module: &Module,
    f: &Function,
    info: &naga::valid::FunctionInfo,
    label: &str,
) -> Vec<String> {
    let mut out = Vec::new();
    for (_, v) in f.local_variables.iter() {
        if holds_array(module, v.ty) {
            let name = v.name.as_deref().unwrap_or("?");
            out.push(format!(
                "{label}: function-scope variable `{name}` holds an array"
            ));
        }
    }
    for a in &f.arguments {
        if holds_array(module, a.ty) {
            let name = a.name.as_deref().unwrap_or("?");
            out.push(format!("{label}: argument `{name}` holds an array"));
        }
    }
    if let Some(r) = &f.result {
        if holds_array(module, r.ty) {
            out.push(format!("{label}: its result holds an array"));
        }
    }
    for (_, e) in f.expressions.iter() {
        if let Expression::Access { base, .. } = e {
            let ty = info[*base].ty.inner_with(&module.types);
            if matches!(ty, TypeInner::Array { .. }) {
                out.push(format!(
                    "{label}: an array value indexed by a variable (index it through its \
                     buffer, or with a constant)"
                ));
            }
        }
    }
    out
}

/// Every breach in the functions reachable from the kernel's entry point.
fn kernel_breaches(name: &str, source: &str) -> Vec<String> {
    let (module, info) = parse(name, source);
    let mut out = Vec::new();
    for (_, g) in module.global_variables.iter() {
        if g.space == naga::AddressSpace::Private && holds_array(&module, g.ty) {
            let var = g.name.as_deref().unwrap_or("?");
            out.push(format!("{name}: private variable `{var}` holds an array"));
        }
    }
    let (index, ep) = module
        .entry_points
        .iter()
        .enumerate()
        .find(|(_, ep)| ep.name == name)
        .unwrap_or_else(|| panic!("{name}: no entry point of that name"));
    out.extend(breaches(
        &module,
        &ep.function,
        info.get_entry_point(index),
        name,
    ));
    let mut todo = Vec::new();
    calls(&ep.function.body, &mut todo);
    let mut seen = Vec::new();
    while let Some(h) = todo.pop() {
        if seen.contains(&h) {
            continue;
        }
        seen.push(h);
        let f = &module.functions[h];
        let label = format!("{name} -> {}", f.name.as_deref().unwrap_or("?"));
        out.extend(breaches(&module, f, &info[h], &label));
        calls(&f.body, &mut todo);
    }
    out
}

#[test]
fn per_step_kernels_keep_their_values_in_registers() {
    let mut all = Vec::new();
    for (name, source) in shaders::ALL {
        if SETUP_KERNELS.iter().any(|(k, _)| *k == name) {
            continue;
        }
        all.extend(kernel_breaches(name, source));
    }
    assert!(
        all.is_empty(),
        "per-step kernels that would use local memory:\n{}",
        all.join("\n")
    );
}

#[test]
fn the_check_finds_each_kind_of_breach() {
    let types = "struct S { nodes: array<u32, 8> }\n";
    let cases = [
        (
            "local",
            "@compute @workgroup_size(1) fn local() { var x: array<f32, 4>; x[1] = 1.0; }",
        ),
        (
            "argument",
            "fn g(a: array<f32, 2>) -> f32 { return a[0]; }
             @compute @workgroup_size(1) fn argument() { let y = g(array<f32, 2>(1.0, 2.0)); }",
        ),
        (
            "value",
            "@group(0) @binding(0) var<storage, read> h: array<S>;
             @compute @workgroup_size(1) fn value(@builtin(local_invocation_index) i: u32) {
                 let e = h[0]; let n = e.nodes[i % 8u];
             }",
        ),
        (
            "constant",
            "const C = array<f32, 2>(1.0, 2.0);
             @compute @workgroup_size(1) fn constant(@builtin(local_invocation_index) i: u32) {
                 let c = C[i % 2u];
             }",
        ),
    ];
    for (name, body) in cases {
        let source = format!("{types}{body}");
        let found = kernel_breaches(name, &source);
        assert!(!found.is_empty(), "{name}: breach not found");
    }
    // indexing a storage buffer's array member through its pointer is allowed
    let ok = format!(
        "{types}@group(0) @binding(0) var<storage, read> h: array<S>;
         @compute @workgroup_size(1) fn ok(@builtin(local_invocation_index) i: u32) {{
             let n = h[0].nodes[i % 8u];
         }}"
    );
    assert_eq!(kernel_breaches("ok", &ok), Vec::<String>::new());
}

#[test]
fn every_setup_kernel_exists() {
    for (k, _) in SETUP_KERNELS {
        assert!(shaders::ALL.iter().any(|(n, _)| *n == k), "{k}");
    }
}
