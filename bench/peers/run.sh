#!/usr/bin/env bash
# The side-by-side comparison against Pinocchio (C++) and MuJoCo (C): the one command.
#
#   bash bench/peers/run.sh [--rounds R] [--batches N] [--quick]     (from the repository root)
#   bash bench/peers/run.sh --python-only    (only the section "From Python", rewritten in place)
#   bash bench/peers/run.sh --throughput-only    (only "Many states per call": its programs alone
#                                                  are built, the section rewritten in place)
#
# 1. a Python venv in target/peers/venv with the pinned wheels (Pinocchio's C++ headers and
#    libraries come with `pin` under site-packages/cmeel.prefix; MuJoCo's C header and library
#    with `mujoco`);
# 2. the timing programs: bench/peers/pinocchio_timing.cpp four times (algorithms compiled
#    here for x86-64-v3 and for this machine's CPU; calls into the wheel's prebuilt library;
#    with OpenMP for the states per second),
#    bench/peers/mujoco_timing.c, and our bench/src/bin/peers.rs three times (x86-64-v3, this
#    machine's CPU, default target; with the feature humanoid-derivatives, the humanoid's
#    derivative outputs), bench/src/bin/throughput.rs and bench/src/bin/contact_steps.rs
#    (x86-64-v3), each rebuilt only when its source or flags changed;
# 3. bench/peers/run.py: values check, timing, callgrind, the speed from Python
#    (bench/python/timing.py), BENCHMARKS.md.
# Everything it builds or installs stays under target/peers/ (ignored by git), but for the
# generated code that timing.py asks `articulated.generate` for (cached in target/pycache).
set -euo pipefail

cd "$(dirname "$0")/../.."
ROOT=$PWD
OUT=$ROOT/target/peers
VENV=$OUT/venv
BIN=$OUT/bin
# The versions the published numbers were measured with; change them here to try others.
# `pin` ships Pinocchio's headers and libraries but not the Eigen and urdfdom headers they
# include (those are only build extras of its wheels), hence cmeel-eigen, cmeel-urdfdom-headers.
REQUIREMENTS="pin==4.1.0 mujoco==4.0.0 cmeel-eigen==3.4.1 cmeel-urdfdom-headers==3.0.0 numpy"
CPU_FLAGS="-march=x86-64-v3"   # the same CPU as RUSTFLAGS="-C target-cpu=x86-64-v3"
# The second pair, both sides built for this machine (RUSTFLAGS="-C target-cpu=native"). The
# stamp holds what gcc makes of it, so that a tree copied to another CPU rebuilds.
NATIVE_FLAGS="-march=native"
NATIVE_CPU=$(g++ -march=native -Q --help=target 2>/dev/null | sed -n 's/^ *-march= *//p' | head -1)

step() { echo "[run.sh] $*"; }

for tool in python3 g++ gcc cargo valgrind sha256sum; do
  command -v "$tool" >/dev/null || { echo "[run.sh] needs $tool on the PATH" >&2; exit 1; }
done

# --- 1. Python venv and wheels -----------------------------------------------------------------
mkdir -p "$OUT" "$BIN"
if [ ! -x "$VENV/bin/python" ]; then
  step "creating the venv $VENV"
  python3 -m venv "$VENV"
fi
if [ "$(cat "$VENV/.requirements" 2>/dev/null)" != "$REQUIREMENTS" ]; then
  step "installing $REQUIREMENTS"
  "$VENV/bin/pip" install --quiet --upgrade pip
  # shellcheck disable=SC2086
  "$VENV/bin/pip" install --quiet $REQUIREMENTS
  echo "$REQUIREMENTS" >"$VENV/.requirements"
fi
THROUGHPUT_ONLY=false
case " $* " in *" --throughput-only "*) THROUGHPUT_ONLY=true ;; esac
# `articulated` for Python (./python, built by maturin; its Rust in target/peers/rust-python, where
# cargo rebuilds only what changed), for bench/python/timing.py: the section "From Python".
if ! $THROUGHPUT_ONLY; then
  step "installing ./python (articulated for Python) into the venv"
  CARGO_TARGET_DIR=$OUT/rust-python "$VENV/bin/pip" install --quiet ./python
fi
SITE=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
PREFIX=$SITE/cmeel.prefix
MJ=$SITE/mujoco
MJLIB=$(ls "$MJ"/libmujoco.so.* | head -1)
for f in "$PREFIX/include/pinocchio/algorithm/rnea.hpp" "$PREFIX/include/eigen3/Eigen/Core" \
  "$PREFIX/include/urdfdom_headers/urdf_model/model.h" "$PREFIX/lib/libpinocchio_parsers.so" \
  "$MJ/include/mujoco/mujoco.h" "$MJLIB"; do
  [ -e "$f" ] || { echo "[run.sh] missing $f: the wheels' layout changed" >&2; exit 1; }
done
# The speed from Python alone needs none of the programs below.
case " $* " in *" --python-only "*)
  step "running bench/peers/run.py $*"
  exec "$VENV/bin/python" bench/peers/run.py "$@" ;;
esac

# --- 2. the timing programs ----------------------------------------------------------------------
# build OUTPUT SOURCE "COMMAND...": runs COMMAND unless OUTPUT exists and was built by the same
# command from the same source (a stamp file beside it holds both).
build() {
  local out=$1 src=$2 cmd=$3
  local stamp="$out.stamp"
  local key
  key="$cmd $(sha256sum "$src")"
  if [ -x "$out" ] && [ "$(cat "$stamp" 2>/dev/null)" = "$key" ]; then
    step "up to date: ${out#"$ROOT"/}"
    return
  fi
  step "compiling ${out#"$ROOT"/}"
  eval "$cmd"
  echo "$key" >"$stamp"
}

# The compile definitions Pinocchio's CMake targets give their users (headers and URDF parser).
PIN_DEFS=$("$VENV/bin/python" - "$PREFIX/lib/cmake/pinocchio/pinocchioTargets.cmake" <<'EOF'
import re, sys
text = open(sys.argv[1]).read()
defs = []
for target in ("pinocchio_headers", "pinocchio_parsers"):
    block = re.search(r"set_target_properties\(pinocchio::%s (.*?)\n\)" % target, text, re.S).group(1)
    found = re.search(r'INTERFACE_COMPILE_DEFINITIONS "([^"]*)"', block)
    defs += [d for d in found.group(1).split(";") if d and "$" not in d] if found else []
print(" ".join("-D" + d for d in dict.fromkeys(defs) if d != "PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION"))
EOF
)
PIN_INC="-I$PREFIX/include -I$PREFIX/include/eigen3 -I$PREFIX/include/urdfdom_headers"
PIN_LIBS="-L$PREFIX/lib -Wl,-rpath,$PREFIX/lib -lpinocchio_parsers -lpinocchio_default"
# omp: the states per second (--throughput), Pinocchio's parallel algorithms (OpenMP).
build_omp() {
  build "$BIN/pinocchio_omp" bench/peers/pinocchio_timing.cpp "g++ -std=c++17 -O3 -DNDEBUG $CPU_FLAGS -fopenmp -DEIGEN_MAX_ALIGN_BYTES=16 \
    -DEIGEN_MALLOC_ALREADY_ALIGNED=1 $PIN_DEFS $PIN_INC bench/peers/pinocchio_timing.cpp \
    -o $BIN/pinocchio_omp $PIN_LIBS"
}
# The states per second alone: Pinocchio's OpenMP build and our `throughput` for three targets.
if $THROUGHPUT_ONLY; then
  step "Pinocchio's OpenMP build, a few minutes when the source changed"
  build_omp
  for target in v3 native default; do
    step "building ours (throughput) for the $target target (cargo, target/peers/rust-$target)"
    case $target in
      v3) flags="-C target-cpu=x86-64-v3" ;;
      native) flags="-C target-cpu=native" ;;
      default) flags="" ;;
    esac
    RUSTFLAGS="$flags" CARGO_TARGET_DIR=$OUT/rust-$target \
      cargo build --release --quiet -p articulated-bench --bin throughput --features humanoid-derivatives
  done
  step "running bench/peers/run.py $*"
  exec "$VENV/bin/python" bench/peers/run.py "$@"
fi
step "Pinocchio: four builds of its headers, a few minutes each when the source changed"
# v3: Pinocchio's algorithms compiled here. The model comes from the wheel's parser library
# (built for baseline x86-64), so Eigen keeps that build's alignment and allocator.
build "$BIN/pinocchio_v3" bench/peers/pinocchio_timing.cpp "g++ -std=c++17 -O3 -DNDEBUG $CPU_FLAGS -DEIGEN_MAX_ALIGN_BYTES=16 \
  -DEIGEN_MALLOC_ALREADY_ALIGNED=1 $PIN_DEFS $PIN_INC bench/peers/pinocchio_timing.cpp \
  -o $BIN/pinocchio_v3 $PIN_LIBS"
# native: the same for this machine's CPU (the comment keys the stamp to the CPU gcc found).
build "$BIN/pinocchio_native" bench/peers/pinocchio_timing.cpp "g++ -std=c++17 -O3 -DNDEBUG $NATIVE_FLAGS -DEIGEN_MAX_ALIGN_BYTES=16 \
  -DEIGEN_MALLOC_ALREADY_ALIGNED=1 $PIN_DEFS $PIN_INC bench/peers/pinocchio_timing.cpp \
  -o $BIN/pinocchio_native $PIN_LIBS # for $NATIVE_CPU"
# wheel: the calls go to the wheel's prebuilt libpinocchio_default, as for a CMake user.
build "$BIN/pinocchio_wheel" bench/peers/pinocchio_timing.cpp "g++ -std=c++17 -O3 -DNDEBUG \
  -DPINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION $PIN_DEFS $PIN_INC bench/peers/pinocchio_timing.cpp \
  -o $BIN/pinocchio_wheel $PIN_LIBS"
build_omp
build "$BIN/mujoco_timing" bench/peers/mujoco_timing.c "gcc -std=c11 -O3 -DNDEBUG $CPU_FLAGS -Wall -I$MJ/include \
  bench/peers/mujoco_timing.c -o $BIN/mujoco_timing $MJLIB -Wl,-rpath,$MJ"

step "building ours for x86-64-v3 (cargo, target/peers/rust-v3)"
RUSTFLAGS="-C target-cpu=x86-64-v3" CARGO_TARGET_DIR=$OUT/rust-v3 \
  cargo build --release --quiet -p articulated-bench --bin peers --bin throughput --bin contact_steps \
  --features humanoid-derivatives
step "building ours for this machine's CPU (cargo, target/peers/rust-native)"
RUSTFLAGS="-C target-cpu=native" CARGO_TARGET_DIR=$OUT/rust-native \
  cargo build --release --quiet -p articulated-bench --bin peers --bin throughput --features humanoid-derivatives
step "building ours for the default target (cargo, target/peers/rust-default)"
env -u RUSTFLAGS CARGO_TARGET_DIR="$OUT/rust-default" \
  cargo build --release --quiet -p articulated-bench --bin peers --bin throughput --features humanoid-derivatives

# --- 3. values check, timing, instructions, BENCHMARKS.md -----------------------------------
step "running bench/peers/run.py $*"
"$VENV/bin/python" bench/peers/run.py "$@"
