#!/usr/bin/env bash
# make install, checked as a user of the installed tree would use it (issue 24, docs/library.md):
# install into a temporary prefix; build a downstream CMake project against it with
# find_package(vdbappear CONFIG) and run it on a golden grid; run installed tools (on the installed
# library, not the build's); read an installed man page with man -l; complete a flag with the
# installed bash completion; ask pkg-config; and see an install into /usr refused before it writes.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/vdbappear-install-XXXXXX")
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix
fail() { echo "install_test: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$prefix" >"$work/install.log" || { cat "$work/install.log"; fail "cmake --install failed"; }

# Every tool, with its man page and its completion.
for tool in "$build"/bin/vdb_*; do
  name=${tool##*/}
  [[ -x $prefix/bin/$name ]] || fail "$name not installed"
  [[ -f $prefix/share/man/man1/$name.1 ]] || fail "no man page for $name"
  [[ -f $prefix/share/bash-completion/completions/$name ]] || fail "no completion for $name"
done
loaded=$(ldd "$prefix/bin/vdb_render" | awk '$1 ~ /^libvdbappear\.so/ { print $3 }')
[[ $(readlink -f "$loaded") == $(readlink -f "$prefix/lib/libvdbappear.so") ]] ||
  fail "the installed vdb_render loads '$loaded', not the installed library"

# The downstream project of docs/library.md.
cmake -S "$source/tests/install/downstream" -B "$work/downstream" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
  >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "find_package(vdbappear) failed"; }
cmake --build "$work/downstream" >"$work/build.log" 2>&1 || { cat "$work/build.log"; fail "the downstream build failed"; }
"$work/downstream/reduce_and_render" "$source/grids/golden/cloud16.vdb" "$work/cloud8.vdb" | tee "$work/run.log"
grep -qE '^[0-9]+ -> [0-9]+ active voxels; mean pixel 0\.[0-9]+ -> 0\.[0-9]+$' "$work/run.log" || fail "unexpected output"
"$work/downstream/density_range" "$work/cloud8.vdb" | grep -qE '^density [0-9.]+ \.\. [0-9.]+$' || fail "density_range"

# Installed tools on PATH, on what the downstream program wrote.
PATH=$prefix/bin:$PATH vdb_sggx_downsample --factor 2 "$work/cloud8.vdb" "$work/cloud4.vdb"
PATH=$prefix/bin:$PATH vdb_preview "$work/cloud4.vdb" -o "$work/cloud4.png" --width 16
[[ -s $work/cloud4.png ]] || fail "vdb_preview wrote nothing"

MANPAGER=cat MANWIDTH=80 man -l "$prefix/share/man/man1/vdb_render.1" >"$work/man.txt" 2>/dev/null
grep -qE "^ +vdb_render +- +renders a medium" "$work/man.txt" || fail "man -l: no NAME line"
grep -q -- "--spp" "$work/man.txt" || fail "man -l: no --spp"

completed=$(PATH=$prefix/bin:$PATH bash -c 'source "$1"; COMP_WORDS=(vdb_render --sp); COMP_CWORD=1; _vdbappear
  printf "%s " "${COMPREPLY[@]}"; COMP_WORDS=(vdb_exemplar_stack as); _vdbappear; printf "%s " "${COMPREPLY[@]}"
  COMP_WORDS=(vdb_make_medium tw); _vdbappear; printf "%s " "${COMPREPLY[@]}"' _ "$prefix/share/bash-completion/completions/vdb_render")
[[ $completed == "--spp assemble twill " ]] || fail "bash completion gave '$completed'"

PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config --cflags --libs vdbappear | grep -q -- "-I$prefix/include" || fail "pkg-config"

if DESTDIR=$work/staged cmake --install "$build" --prefix /usr >"$work/usr.log" 2>&1; then fail "an install into /usr was not refused"; fi
grep -q "will not install into /usr" "$work/usr.log" || fail "the refusal does not say why"
[[ ! -e $work/staged ]] || fail "the refused install wrote $(find "$work/staged" -type f | head -1)"
echo "install_test: passed"
