#!/usr/bin/env bash
# A private apt for Debian 13 (trixie) packages, beside the machine's own:
# its own sources list, lists, cache and status under a folder of the
# build's, never the machine's sources or dpkg database. The mirror is the
# one the machine's apt already uses for Debian 12.
#   source scripts/debian13_apt.sh; debian13_apt_init DIR; debian13_apt download PKG...
debian13_mirror() {
  local uri=""
  if [[ -f /etc/apt/sources.list.d/debian.sources ]]; then
    uri=$(awk '/^URIs:/ && $2 !~ /security/ {print $2; exit}' /etc/apt/sources.list.d/debian.sources)
  fi
  if [[ -z $uri && -f /etc/apt/sources.list ]]; then
    uri=$(awk '$1 == "deb" && $0 !~ /security/ {for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) {print $i; exit}}' /etc/apt/sources.list)
  fi
  [[ -n $uri ]] || { echo "debian13_apt: no Debian mirror in the machine's apt sources" >&2; return 1; }
  echo "$uri"
}

DEBIAN13_APT_DIR=""
debian13_apt_init() {
  mkdir -p "$1"
  DEBIAN13_APT_DIR=$(realpath "$1")
  local mirror
  mirror=$(debian13_mirror) || return 1
  mkdir -p "$DEBIAN13_APT_DIR"/{lists/partial,cache/archives/partial}
  echo "deb [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $mirror trixie main" \
    >"$DEBIAN13_APT_DIR/sources.list"
  : >"$DEBIAN13_APT_DIR/status"
  # Lists older than a day are fetched again.
  if [[ -z $(find "$DEBIAN13_APT_DIR/lists" -maxdepth 1 -name '*_Packages*' -mmin -1440 2>/dev/null) ]]; then
    debian13_apt update -qq || { echo "debian13_apt: apt-get update of trixie failed" >&2; return 1; }
  fi
}

debian13_apt() {
  apt-get -o Dir::Etc::SourceList="$DEBIAN13_APT_DIR/sources.list" -o Dir::Etc::SourceParts=/dev/null \
    -o Dir::State::Lists="$DEBIAN13_APT_DIR/lists" -o Dir::Cache="$DEBIAN13_APT_DIR/cache" \
    -o Dir::State::Status="$DEBIAN13_APT_DIR/status" -o Debug::NoLocking=1 \
    -o APT::Sandbox::User=root "$@"
}
