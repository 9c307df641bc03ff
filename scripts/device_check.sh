#!/usr/bin/env bash
# The GPU checks and timings on a GPU machine without a Rust toolchain or Vulkan loader, in
# one call (docs/performance.md, "Measuring on a GPU"): the GPU twin and run tests, then the shipped drop-weight
# and indentation scenes on the GPU and on the device machine's CPU, their summaries and a
# table of wall times written to $OUT.
#
#   bash scripts/device_check.sh prepare   # here: the loader packages (.gl/), the stripped
#                                          # binaries and the project (.gpu/)
#   bash scripts/device_check.sh device    # there, with carry [".gl", ".gpu"]
#   bash scripts/device_check.sh pack-bench LABEL   # here: this build's explicit_step and
#                                                   # kernels benches
#   bash scripts/device_check.sh bench ARGS         # there: every packed explicit_step
#                                                   # bench with ARGS
#   bash scripts/device_check.sh kernels ARGS       # there: every packed kernels bench
#   bash scripts/device_check.sh pack-ranks         # here: OpenMPI's runtime (.gl/mpi/),
#                                                   # impact with MPI and the ranks bench
#   bash scripts/device_check.sh ranks ARGS         # there: the ranks bench with ARGS, e.g.
#                                                   # --gpu --floor-only --floor 8 --ranks 1,2
#
# The test binaries look for scenes at the path they were built in, so the device unpacks the
# project there.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
tests=(gpu_contact gpu_kernels gpu_damage gpu_cohesive gpu_runs gpu_explicit rigid_bodies drop_weight cohesive)

# Downloads Debian packages (amd64) into folder $1 of .gl/, which git ignores.
download() {
    local folder=.gl/$1
    shift
    cd "$here"
    grep -qx '/.gl/' .git/info/exclude || printf '/.gl/\n/.gpu/\n' >> .git/info/exclude
    mkdir -p "$folder" /tmp/amd64/partial
    o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
    # shellcheck disable=SC2086
    apt-get $o update >/dev/null
    # shellcheck disable=SC2086
    (cd "$folder" && apt-get $o download "$@")
}

# The Vulkan loader and GL libraries the device machine lacks (.gl/*.deb).
loader() {
    if ! ls "$here"/.gl/libvulkan1_*.deb >/dev/null 2>&1; then
        download . libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2
    fi
}

# On the device machine: the Vulkan loader unpacked, and wgpu on NVIDIA's Vulkan driver
# (VK_DRIVER_FILES may name another, for a check elsewhere).
use_card() {
    for f in "$here"/.gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
    export VK_DRIVER_FILES=${VK_DRIVER_FILES:-/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json}
    export WGPU_BACKEND=vulkan
}

prepare() {
    loader
    cd "$here"
    cargo build --release --all-targets
    rm -rf .gpu && mkdir -p .gpu/bin
    for t in "${tests[@]}"; do
        f=$(ls -t target/release/deps/"$t"-* | grep -v '\.d$' | head -1)
        strip -o .gpu/bin/"$t" "$f"
    done
    strip -o .gpu/bin/impact target/release/impact
    # xz over the whole folder: the binaries share most of their code, and gzip's window
    # cannot see it (56 MB against 12, where the device takes 64 MiB in all)
    tar cf - -C .gpu bin | xz -9 -T0 > .gpu/bin.txz && rm -rf .gpu/bin
    git archive --format=tar.gz HEAD > .gpu/project.tgz
    du -sh .gl .gpu
}

device() {
    use_card
    bin=$(mktemp -d)
    tar xJf "$here"/.gpu/bin.txz -C "$bin" 2>/dev/null ||
        python3 -c 'import sys, tarfile; tarfile.open(sys.argv[1]).extractall(sys.argv[2])' \
            "$here"/.gpu/bin.txz "$bin"
    B=$bin/bin
    mkdir -p "$here"
    tar xzf "$here"/.gpu/project.tgz -C "$here"
    cd "$here"
    # where the tests write their runs (CARGO_TARGET_TMPDIR, the build's path), and the binary
    # the CLI tests run (CARGO_BIN_EXE_impact, the build's path too)
    mkdir -p target/tmp target/release
    cp "$B"/impact target/release/impact
    # the device tool brings back only a few files: everything goes into results.tgz, the
    # table and the failures beside it
    final=${OUT:-/tmp/out}
    out=$(mktemp -d)
    mkdir -p "$final"
    "$B"/impact info | tee "$out"/info.txt
    for t in "${tests[@]}"; do
        "$B"/"$t" 2>&1 | tail -40 > "$out"/test_"$t".txt || echo "$t: FAILED" >> "$out"/failures.txt
    done
    printf '| scene | device | engine | steps | wall s |\n|---|---|---|---:|---:|\n' > "$out"/times.md
    # the damaged drop weight's first 0.3 ms on both devices (its whole run takes about ten
    # minutes on sixteen cores), and the whole of it on the GPU (resident, its plies' damage
    # and cohesive pairs on the device)
    sed 's/^end_time = .*/end_time = 3e-4/' scenes/drop_weight_d7136.toml \
        > scenes/drop_weight_d7136_first_0.3ms.toml
    for s in drop_weight_d7136_elastic drop_weight_d7136_first_0.3ms indentation_d6264 drop_weight_d7136; do
        devices="gpu cpu"
        [ "$s" = drop_weight_d7136 ] && devices=gpu
        for d in $devices; do
            dir=$(mktemp -d)
            "$B"/impact run scenes/$s.toml --device $d --out "$dir" > "$out"/run_${s}_$d.txt 2>&1 || true
            cp "$dir"/summary.json "$out"/summary_${s}_$d.json 2>/dev/null || true
            field() { grep -o "\"$1\": [^,]*" "$dir"/summary.json | head -1 | sed 's/.*: //; s/"//g'; }
            echo "| $s | $d | $(field engine) | $(field steps) | $(field wall_seconds) |" >> "$out"/times.md
        done
    done
    cat "$out"/times.md
    cp "$out"/times.md "$final"/
    if [ -f "$out"/failures.txt ]; then cp "$out"/failures.txt "$final"/; fi
    tar czf "$final"/results.tgz -C "$out" .
}

# Packs this build's explicit_step and kernels benches as .gpu/bench/<bench>_<label> (several
# labels side by side: a build before a change and after it, timed in one call on one card).
pack_bench() {
    cd "$here"
    label=${1:?a label}
    cargo build --release --bench explicit_step --bench kernels
    mkdir -p .gpu/bench
    for b in explicit_step kernels; do
        f=$(ls -t target/release/deps/"$b"-* | grep -v '\.d$' | head -1)
        strip -o .gpu/bench/"$b"_"$label" "$f"
        gzip -f .gpu/bench/"$b"_"$label"
    done
    du -sh .gpu/bench
}

# Runs every packed bench $1 (explicit_step or kernels) with the arguments after it, in
# label order, each table into $OUT/<bench>_<label>.md.
run_benches() {
    use_card
    name=$1
    shift
    final=${OUT:-/tmp/out}
    mkdir -p "$final"
    dir=$(mktemp -d)
    for g in "$here"/.gpu/bench/"$name"_*.gz; do
        label=$(basename "$g" .gz)
        label=${label#"$name"_}
        gunzip -c "$g" > "$dir/$label" && chmod +x "$dir/$label"
        "$dir/$label" "$@" 2>&1 | tee "$final/${name}_$label.md" | tail -5
    done
}

# OpenMPI 4.1's runtime on Debian 12 and what it needs beyond a base system (libc6,
# libstdc++6 and the packages of priority required or important); no ssh client: one node
# launches its ranks itself (OMPI_MCA_plm=isolated).
mpi_packages=(openmpi-bin openmpi-common libopenmpi3 libpmix2 libevent-core-2.1-7
    libevent-pthreads-2.1-7 libhwloc15 libhwloc-plugins libfabric1 libibverbs1
    ibverbs-providers librdmacm1 libnl-3-200 libnl-route-3-200 libucx0 libpsm2-2
    libpsm-infinipath1 libmunge2 libnuma1 libatomic1 libpciaccess0 libudev1 libuuid1
    libxml2 libicu72 libx11-6 libx11-data libxau6 libxcb1 libxdmcp6 libxext6 libxnvctrl0
    ocl-icd-libopencl1 libbsd0 libmd0 liblzma5 zlib1g)

# Packs OpenMPI's runtime packages (.gl/mpi/), and impact built with MPI and the ranks bench
# (.gpu/ranks.tgz): the bench runs `mpirun ... impact run` at the path it was built in.
pack_ranks() {
    loader
    download mpi "${mpi_packages[@]}"
    cd "$here"
    cargo build --release --features mpi --bench ranks --bin impact
    rm -rf .gpu/ranks && mkdir -p .gpu/ranks
    f=$(ls -t target/release/deps/ranks-* | grep -v '\.d$' | head -1)
    strip -o .gpu/ranks/ranks "$f"
    strip -o .gpu/ranks/impact target/release/impact
    tar czf .gpu/ranks.tgz -C .gpu ranks && rm -rf .gpu/ranks
    du -sh .gl/mpi .gpu/ranks.tgz
}

# Installs the packed MPI runtime where it is missing (files already there are kept), and
# the `mpirun` link its package's setup would make.
install_mpi() {
    staging=$(mktemp -d)
    for f in "$here"/.gl/mpi/*.deb; do dpkg -x "$f" "$staging"; done
    # (merged /usr: /lib is a link to usr/lib, which stays)
    tar -C "$staging" -cf - . | tar -C / -xf - --skip-old-files --keep-directory-symlink
    # the links their packages' setup scripts make
    [ -e /usr/bin/mpirun ] || ln -s orterun /usr/bin/mpirun
    psm=/usr/lib/x86_64-linux-gnu/libpsm_infinipath.so.1
    [ -e $psm ] || ln -s /usr/lib/libpsm1/libpsm_infinipath.so.1.16 $psm
    ldconfig
}

# Runs the ranks bench with the arguments given, its tables into $OUT/ranks.md.
ranks() {
    use_card
    install_mpi
    # no ssh: one node launches its ranks itself
    export OMPI_MCA_plm=isolated
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    final=${OUT:-/tmp/out}
    mkdir -p "$final"
    bin=$(mktemp -d)
    tar xzf "$here"/.gpu/ranks.tgz -C "$bin"
    mkdir -p "$here"/target/release "$here"/target/tmp
    cp "$bin"/ranks/impact "$here"/target/release/impact
    cd "$here"
    "$bin"/ranks/ranks "$@" 2>&1 | tee "$final"/ranks.md
}

case "${1:-}" in
prepare) prepare ;;
device) device ;;
pack-bench) pack_bench "${2:-}" ;;
bench) shift; run_benches explicit_step "$@" ;;
kernels) shift; run_benches kernels "$@" ;;
pack-ranks) pack_ranks ;;
ranks) shift; ranks "$@" ;;
*) echo "usage: $0 prepare|device|pack-bench LABEL|bench ARGS|kernels ARGS|pack-ranks|ranks ARGS" >&2; exit 2 ;;
esac
