#!/usr/bin/env bash
# Install.ExamplesBuildAgainstThePackage: installs lambert from a build tree into a scratch
# prefix, checks that the installed headers are exactly the public API (lambert/lambert.h and the
# lambert headers it reaches, each compiling on its own), and builds examples/ against it as
# another project would (find_package(lambert), lambert::lambert), then runs the programs. Each
# step is named; the first that fails ends the test with its name.
#
#   tests/install_test.sh BUILD_DIR SOURCE_DIR SCRATCH_DIR
#
# SCRATCH_DIR is removed first and holds the prefix, the examples' build and their output.
set -uo pipefail

if [ $# -ne 3 ]; then
  echo "usage: $0 BUILD_DIR SOURCE_DIR SCRATCH_DIR" >&2
  exit 2
fi
build=$(cd "$1" && pwd) || exit 2
source=$(cd "$2" && pwd) || exit 2
scratch=$3
case "$scratch" in
  "" | / | "$build" | "$source") echo "install_test: refusing to use '$scratch' as the scratch directory" >&2; exit 2 ;;
esac

step=""
started=$SECONDS
begin() {
  step=$1
  echo "== install_test: $step"
}
fail() {
  echo "install_test: FAILED in step '$step': $*" >&2
  exit 1
}
# Runs a command of the current step; its failure fails the step.
run() {
  "$@" || fail "'$*' exited with status $?"
}

begin "clear the scratch directory"
run rm -rf "$scratch"
run mkdir -p "$scratch"
scratch=$(cd "$scratch" && pwd) || fail "cannot enter $scratch"  # absolute: CMake is run from elsewhere
prefix=$scratch/prefix

# The library directory the build tree installs to (GNUInstallDirs: lib on Debian).
cache_value() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
libdir=$(cache_value CMAKE_INSTALL_LIBDIR)
libdir=${libdir:-lib}
case "$libdir" in /*) begin "read the build's settings"; fail "CMAKE_INSTALL_LIBDIR is absolute ($libdir); the test installs into its own prefix" ;; esac

begin "cmake --install $build --prefix $prefix"
run cmake --install "$build" --prefix "$prefix"

begin "the prefix holds the CLI, both libraries, the headers and the package"
for file in bin/lambert "$libdir/liblambert.a" include/lambert/lambert.h include/lambert/engine/radiosity.h include/lambert/version.h \
  "$libdir/cmake/lambert/lambertConfig.cmake" "$libdir/cmake/lambert/lambertConfigVersion.cmake" \
  "$libdir/cmake/lambert/lambertTargets.cmake"; do
  [ -f "$prefix/$file" ] || fail "$prefix/$file is missing"
done
[ -x "$prefix/bin/lambert" ] || fail "$prefix/bin/lambert is not executable"
compgen -G "$prefix/$libdir/liblambert.so*" > /dev/null || fail "no $prefix/$libdir/liblambert.so*"

begin "internal headers are not installed"
for internal in formfactor/kernels.h flat/hemicube.h geometry/coverage.h solve/progressive_shooter.h \
  method/method.h core/parallel.h hierarchical/links.h formfactor/matrix.h flat/form_factors.h \
  hierarchical/element_hierarchy.h flat/quadtree.h solve/solver.h solve/transport.h \
  method/point_gather.h engine/solution_internals.h hierarchical/method.h flat/uniform_method.h; do
  [ ! -e "$prefix/include/lambert/$internal" ] || fail "internal header lambert/$internal is installed"
done
if grep -rlE '#include <embree' "$prefix/include" > "$scratch/embree-headers.txt"; then
  fail "installed headers include Embree: $(tr '\n' ' ' < "$scratch/embree-headers.txt")"
fi

# The lambert headers a header includes, as "lambert/…" or <lambert/…>.
lambert_includes() { sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]\(lambert\/[^">]*\)[">].*/\1/p' "$1"; }

begin "every lambert header an installed header includes is installed"
while IFS= read -r header; do
  for included in $(lambert_includes "$header"); do
    [ -f "$prefix/include/$included" ] || fail "${header#"$prefix/include/"} includes $included, which is not installed"
  done
done < <(find "$prefix/include" -name '*.h')

begin "every installed header is reached from lambert/lambert.h (the public API and nothing else)"
declare -A reached=()
pending=(lambert/lambert.h)
while [ ${#pending[@]} -gt 0 ]; do
  header=${pending[-1]}
  unset 'pending[-1]'
  [ -n "${reached[$header]:-}" ] && continue
  reached[$header]=1
  for included in $(lambert_includes "$prefix/include/$header"); do pending+=("$included"); done
done
while IFS= read -r header; do
  [ -n "${reached[${header#"$prefix/include/"}]:-}" ] || fail "${header#"$prefix/include/"} is installed, but lambert/lambert.h does not reach it"
done < <(find "$prefix/include" -name '*.h')

begin "every installed header compiles on its own"
compiler=$(cache_value CMAKE_CXX_COMPILER)
mkdir -p "$scratch/headers" || fail "cannot make $scratch/headers"
while IFS= read -r header; do
  name=${header#"$prefix/include/"}
  unit=$scratch/headers/$(tr '/' '_' <<< "${name%.h}").cpp
  echo "#include <$name>" > "$unit"
  "${compiler:-c++}" -std=c++20 -fsyntax-only -I"$prefix/include" "$unit" > "$unit.log" 2>&1 ||
    fail "#include <$name> alone does not compile: $(head -c 2000 "$unit.log")"
done < <(find "$prefix/include" -name '*.h' | sort)
echo "$(find "$prefix/include" -name '*.h' | wc -l) headers"

begin "lambert --version"
version=$(sed -n 's/^#define LAMBERT_VERSION_STRING "\(.*\)"$/\1/p' "$prefix/include/lambert/version.h")
[ -n "$version" ] || fail "no LAMBERT_VERSION_STRING in $prefix/include/lambert/version.h"
printed=$("$prefix/bin/lambert" --version) || fail "exited with status $?"
[ "$printed" = "lambert $version" ] || fail "printed '$printed', expected 'lambert $version'"

begin "configure examples/ against the prefix"
run cmake -S "$source/examples" -B "$scratch/examples-build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$(cache_value CMAKE_CXX_COMPILER)"
found=$(sed -n 's/^lambert_DIR:PATH=//p' "$scratch/examples-build/CMakeCache.txt")
[ "$found" = "$prefix/$libdir/cmake/lambert" ] || fail "find_package(lambert) found '$found', not the prefix's package"

begin "build examples/"
run cmake --build "$scratch/examples-build" -j2

bin=$scratch/examples-build
begin "solve_cornell_shared runs on the prefix's liblambert.so"
# ldd's output taken whole first: `ldd | grep -q` under pipefail fails when grep stops reading early.
linked=$(ldd "$bin/solve_cornell_shared")
grep -q "liblambert.so.* => $prefix/$libdir/liblambert.so" <<< "$linked" ||
  fail "it is not linked to $prefix/$libdir/liblambert.so: $(grep lambert <<< "$linked")"
output=$("$bin/solve_cornell_shared") || fail "exited with status $?"
echo "$output"
[[ "$output" =~ ^[0-9]+\ vertices,\ mean\ radiance\ 0\.[0-9]+ ]] || fail "printed '$output'"

begin "bake tests/data/blender_room.glb"
run "$bin/bake" "$source/tests/data/blender_room.glb" "$scratch/baked.glb"
[ -s "$scratch/baked.glb" ] || fail "$scratch/baked.glb was not written"
[ "$(head -c 4 "$scratch/baked.glb")" = "glTF" ] || fail "$scratch/baked.glb does not start with the glTF magic"

begin "moving_light"
run "$bin/moving_light"

pydir=$(cache_value LAMBERT_PYTHON_DIR)
if [ -n "$pydir" ]; then
  begin "the installed Python module imports from $prefix/$pydir and solves"
  python=$(cache_value Python3_EXECUTABLE)
  where=$(cd "$scratch" && PYTHONPATH="$prefix/$pydir" XDG_CACHE_HOME="$scratch/cache" "${python:-python3}" -c '
import lambert
engine = lambert.Radiosity(lambert.load_scene("cornell"))
assert engine.solve()["converged"]
assert engine.vertex_radiance().shape[1] == 3
print(lambert.__file__)') || fail "it did not import or solve"
  [[ "$where" == "$prefix/$pydir/"* ]] || fail "imported from $where, not the prefix"
fi

echo "install_test: passed in $((SECONDS - started)) s"
