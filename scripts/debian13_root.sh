#!/usr/bin/env bash
# A minimal Debian 13 (trixie) root for the Blender 5.1+ suites: Blender 5.1
# and later embed Python 3.13, whose bpy wheels need a 3.13 interpreter, and
# trixie's needs glibc 2.38 (Debian 12 has 2.36), so it runs in this root.
#   bash scripts/debian13_root.sh make          makes build/debian13-root (once;
#                                               again when the recipe below changes)
#   bash scripts/debian13_root.sh run CMD ARG…  runs CMD in the root, in this
#                                               checkout (bound at the same path)
#   bash scripts/debian13_root.sh venv LINE PIN  makes /opt/venv-bpy-LINE in the
#                                               root (bpy PIN from PyPI), once
# `run` works in a private mount namespace (unshare): /proc, /dev, /sys, the
# checkout, pip's cache and the host's /usr (read-only, for the host's idiff)
# are bound there and vanish with the namespace on every exit path.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD
source scripts/debian13_apt.sh
root=$repo/build/debian13-root
# python3.13 and venv; the GL dispatch libraries (libEGL, libGL, libOpenGL,
# libGLX: never vendored in the wheel) and Mesa (llvmpipe); the X, Wayland and
# font libraries bpy's bundled libraries load; tzdata for Python's zoneinfo.
packages=(python3.13 python3.13-venv libpython3.13 libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0 libgl1 libglx0 libglx-mesa0
  libx11-6 libxext6 libxi6 libxxf86vm1 libxfixes3 libxrender1 libxkbcommon0 libxrandr2 libxcursor1
  libxinerama1 libsm6 libice6 libwayland-client0 libwayland-egl1 libwayland-cursor0 libdecor-0-0 libdbus-1-3
  libfontconfig1 tzdata)
recipe="trixie minbase ${packages[*]} v2"

fail() { echo "debian13_root: $*" >&2; exit 1; }

make_root() {
  if [[ -f $root/.recipe && $(cat "$root/.recipe") == "$recipe" ]]; then return; fi
  command -v debootstrap >/dev/null || fail "debootstrap missing (scripts/install_deps.sh --tests)"
  local mirror list start=$SECONDS
  mirror=$(debian13_mirror) || fail "no Debian mirror in the machine's apt sources"
  rm -rf "$root" "$root.tmp"
  list=$(IFS=,; echo "${packages[*]}")
  mkdir -p build/debian13-debs
  echo "debian13_root: debootstrap trixie (minbase + ${#packages[@]} packages) into $root"
  if ! debootstrap --variant=minbase --include="$list" --cache-dir="$repo/build/debian13-debs" \
       --keyring=/usr/share/keyrings/debian-archive-keyring.gpg trixie "$root.tmp" "$mirror" \
       >build/debian13-debootstrap.log 2>&1; then
    tail -n 20 build/debian13-debootstrap.log >&2
    fail "debootstrap failed (build/debian13-debootstrap.log)"
  fi
  rm -rf "$root.tmp"/var/cache/apt/archives/*.deb
  # pip in the root trusts what the host's pip trusts.
  cp /etc/ssl/certs/ca-certificates.crt "$root.tmp/etc/ssl/certs/ca-certificates.crt" 2>/dev/null ||
    { mkdir -p "$root.tmp/etc/ssl/certs" && cp /etc/ssl/certs/ca-certificates.crt "$root.tmp/etc/ssl/certs/"; }
  [[ -f /etc/pip.conf ]] && cp /etc/pip.conf "$root.tmp/etc/pip.conf"
  # The host's idiff (openimageio-tools), run with the host's loader and
  # libraries from the read-only /host/usr: Debian 13's OpenImageIO is 570 MB.
  cat >"$root.tmp/usr/local/bin/idiff" <<'SH'
#!/bin/sh
lib=/host/usr/lib/x86_64-linux-gnu
exec $lib/ld-linux-x86-64.so.2 --library-path $lib:$lib/blas:$lib/lapack:/host/usr/lib /host/usr/bin/idiff "$@"
SH
  chmod +x "$root.tmp/usr/local/bin/idiff"
  mkdir -p "$root.tmp/host/usr" "$root.tmp$repo" "$root.tmp/root/.cache/pip"
  # Blender lists the mounted file systems from /etc/mtab (a warning without it).
  ln -sf ../proc/self/mounts "$root.tmp/etc/mtab"
  echo "$recipe" >"$root.tmp/.recipe"
  mv "$root.tmp" "$root"
  echo "debian13_root: made in $((SECONDS - start)) s"
}

run_in_root() {
  [[ -f $root/.recipe ]] || fail "no root: run 'scripts/debian13_root.sh make' first"
  mkdir -p "$HOME/.cache/pip"
  # The checkout first: a later bind inside it would show up again under it.
  local binds=("$repo:$repo" /proc:/proc /dev:/dev /sys:/sys "$HOME/.cache/pip:/root/.cache/pip")
  [[ -d /opt/wheels ]] && binds+=(/opt/wheels:/opt/wheels) && mkdir -p "$root/opt/wheels"
  # Each bind is made, or the command does not run; the host's /usr is read-only.
  local script='set -e; root=$1; shift; n=$1; shift
    for ((i = 0; i < n; i++)); do from=${1%%:*}; to=${1#*:}; shift
      mount --rbind "$from" "$root$to" || { echo "debian13_root: cannot bind $from" >&2; exit 1; }
    done
    mount --bind /usr "$root/host/usr" && mount -o remount,bind,ro "$root/host/usr" ||
      { echo "debian13_root: cannot bind /usr read-only at /host/usr" >&2; exit 1; }
    cd "$PWD"; exec chroot "$root" /usr/bin/env -C "$PWD" "$@"'
  unshare --mount --propagation private bash -c "$script" bash "$root" "${#binds[@]}" "${binds[@]}" \
    env HOME=/root PATH=/usr/local/bin:/usr/bin:/bin LANG=C.UTF-8 "$@"
}

# numpy and pytest as Blender 5.1+ ship them (bpy asks numpy >= 2.2, < 3).
bpy_venv() {
  local line=$1 pin=$2 venv=/opt/venv-bpy-$1
  local want="bpy==$pin numpy==2.3.5 pytest==8.3.4"
  if [[ -x $root$venv/bin/python && -f $root$venv/.pins && $(cat "$root$venv/.pins") == "$want" ]]; then return; fi
  echo "debian13_root: $venv (bpy $pin from PyPI)"
  rm -rf "${root:?}$venv"
  run_in_root python3.13 -m venv "$venv" || fail "python3.13 -m venv $venv failed"
  # shellcheck disable=SC2086
  run_in_root "$venv/bin/python" -m pip install -q $want || fail "pip install $want failed in $venv"
  echo "$want" >"$root$venv/.pins"
}

case ${1:-} in
  make) make_root ;;
  run) shift; run_in_root "$@" ;;
  venv) shift; [[ $# == 2 ]] || fail "usage: scripts/debian13_root.sh venv LINE PIN"; bpy_venv "$@" ;;
  *) fail "usage: scripts/debian13_root.sh make | run CMD [ARG…] | venv LINE PIN" ;;
esac
