#!/bin/bash
# Build LinuxCNC's interpreter library (librs274.so.0) at the commit of Debian's
# linuxcnc-uspace 2.9.0 package (f1270d6ed7) with LinuxCNC's two fixes of issue #1785
# (b1f3e7d8b8, f648d01c72: G70 with cutter compensation, first released in v2.9.3), so that
# Debian's own `rs274` runs with the fixed interpreter:
#
#   tests/realworld/rs274_fixed/build.sh LINUXCNC_GIT_DIR OUT_DIR
#   LD_LIBRARY_PATH=OUT_DIR rs274 -t tools.tbl -g PROGRAM OUT
#
# LINUXCNC_GIT_DIR is a clone (or bare mirror) of https://github.com/LinuxCNC/linuxcnc that
# has those three commits. Needs g++, python3-dev and Boost.Python headers
# (libboost-python-dev). Only the interpreter is rebuilt; every other library is Debian's.
set -euo pipefail
git_dir=$1
out=$(realpath -m "$2")
base=f1270d6ed7
fixes="b1f3e7d8b8 f648d01c72"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
cd "$work"
# a partial (blobless) mirror may lack files outside src/: git archive then complains after
# writing src/, which is all this needs
{ git --git-dir="$git_dir" archive "$base" src 2>/dev/null || true; } | tar x
test -f src/emc/rs274ngc/interp_g7x.cc
for c in $fixes; do
  git --git-dir="$git_dir" show "$c" -- src/emc/rs274ngc/interp_g7x.cc | patch -p1 --quiet
done
mkdir cfg
version=$(strings /lib/librs274.so.0 | awk '/^2\.9/ {print; exit}') || true
version=${version:-2.9.0~pre1}
printf '#define EMC2_HOME "/usr"\n#define PACKAGE_VERSION "%s"\n' "$version" > cfg/config.h
inc="-Icfg -Isrc -Isrc/emc/rs274ngc -Isrc/emc/nml_intf -Isrc/emc -Isrc/rtapi -Isrc/hal
 -Isrc/libnml/inifile -Isrc/libnml/posemath -Isrc/libnml -Isrc/libnml/nml -Isrc/libnml/cms
 -Isrc/libnml/rcs -Isrc/libnml/buffer -Isrc/libnml/os_intf -Isrc/libnml/linklist
 -Isrc/emc/tooldata -Isrc/emc/motion -Isrc/emc/pythonplugin
 -I$(python3 -c 'import sysconfig; print(sysconfig.get_paths()["include"])')"
# the sources of librs274 (LIBRS274SRCS of src/emc/rs274ngc/Submakefile)
sources=$(sed -n '/^LIBRS274SRCS/,/)/p' src/emc/rs274ngc/Submakefile | grep -o '[a-z_0-9]*\.cc')
mkdir obj
for s in $sources; do
  g++ -std=gnu++17 -O2 -fPIC -DULAPI -DBOOST_BIND_GLOBAL_PLACEHOLDERS $inc \
    -c "src/emc/rs274ngc/$s" -o "obj/${s%.cc}.o"
done
pyver=$(python3 -c 'import sys; print(f"{sys.version_info[0]}{sys.version_info[1]}")')
g++ -shared -Wl,-soname,librs274.so.0 -o "$out/librs274.so.0" obj/*.o \
  /lib/liblinuxcncini.so.0 /lib/libpyplugin.so.0 /lib/liblinuxcnchal.so.0 \
  /lib/libtooldata.so.0 -lstdc++ "-lboost_python$pyver" \
  "-lpython$(python3 -c 'import sysconfig; print(sysconfig.get_config_var("LDVERSION"))')"
echo "built $out/librs274.so.0"
