#!/usr/bin/env bash
# Runs commands as a new user would, on a bare Debian 12 machine: a minimal root made with
# debootstrap (minbase + git, sudo, ca-certificates; nothing else), a fresh clone of the project's
# committed HEAD in it, each command run there in turn as root with an empty environment.
#
#   scripts/fresh_check.sh 'CMD1' ['CMD2' ...]   the given commands
#   scripts/fresh_check.sh --readme               the commands of README.md's quick start
#   scripts/fresh_check.sh --print-readme         print those commands, one a line, and exit
#
# With --readme the check also requires what the main job promises to write (results/REPORT.md
# and results/plots/*.png) to have been written anew in the clone, not merely checked out.
# Exit status: 0 when every command exits 0 (and every expected file is new), else 1.
#
# The pristine root is made once and cached at $BASE; each check works on a fresh copy of it
# ($ROOT), so nothing one check installs is there for the next. Needs root (debootstrap, chroot,
# bind mounts) and the Debian package registry. Each command's log: /tmp/fresh-cmdN.log.
#
# CCACHE_STORE=DIR (CI sets it to the store its own builds just filled): the root copy gets one
# package more, ccache, and DIR is mounted in it as the commands' compiler cache, so a file the
# host's build of the same commit compiled is not compiled again. Everything else is as bare: a
# header or library setup.sh fails to install still fails the build, since ccache runs the
# preprocessor whenever an included file is not where it was. Unset (the default, and what to
# run before a change lands), the commands compile from nothing, as a new user's do.
#
# PUPPET_MAIN_QUICK=1 is passed on to the commands (CI sets it: the main job then runs each stage
# on a fraction of its work, scripts/main.sh); unset, the main job runs whole.
set -u
BASE=${BASE:-/tmp/fresh-base}
ROOT=${ROOT:-/tmp/fresh-root}
SRC=${SRC:-$(git -C "$(dirname "$0")" rev-parse --show-toplevel 2>/dev/null)}
[ -n "$SRC" ] || { echo "fresh-check: run it inside the project's clone (or set SRC)"; exit 1; }

# the quick start's commands: the first ```sh block after "## Quick start", one command a line,
# a trailing "# comment" and surrounding blanks removed
readme_commands() {
  awk '/^## Quick start/ { section = 1; next }
       section && /^```sh/ { block = 1; next }
       block && /^```/ { exit }
       block { sub(/[[:space:]]+#.*$/, ""); sub(/^[[:space:]]+/, ""); if ($0 != "") print }' \
    "$SRC/README.md"
}

expect=()
if [ "${1:-}" = "--print-readme" ] || [ "${1:-}" = "--readme" ]; then
  mapfile -t commands < <(readme_commands)
  if [ ${#commands[@]} -ne 2 ]; then
    echo "fresh-check: README.md's quick start has ${#commands[@]} commands, expected 2"
    exit 1
  fi
  if [ "$1" = "--print-readme" ]; then
    printf '%s\n' "${commands[@]}"
    exit 0
  fi
  set -- "${commands[@]}"
  expect=("results/REPORT.md" "results/plots/*.png")
fi
[ $# -gt 0 ] || { echo "usage: fresh_check.sh 'CMD1' ['CMD2' ...] | --readme | --print-readme"; exit 1; }
[ "$(id -u)" -eq 0 ] || { echo "fresh-check: needs root (debootstrap, chroot)"; exit 1; }

MIRROR=$(sed -n 's/^URIs: //p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -n 1)
if [ ! -x "$BASE/bin/bash" ]; then
  SECONDS=0
  if ! command -v debootstrap >/dev/null; then
    { apt-get update -qq && apt-get install -y -qq debootstrap; } >/dev/null 2>&1 ||
      { echo "fresh-check: could not install debootstrap"; exit 1; }
  fi
  rm -rf "$BASE"
  debootstrap --variant=minbase --include=ca-certificates,git,sudo bookworm "$BASE" $MIRROR \
    >/tmp/fresh-debootstrap.log 2>&1 ||
    { tail -n 5 /tmp/fresh-debootstrap.log; echo "fresh-check: debootstrap failed"; exit 1; }
  cp /etc/resolv.conf "$BASE/etc/resolv.conf" 2>/dev/null
  echo "== bare root made in ${SECONDS}s"
fi

unmount() { umount "$ROOT/ccache" "$ROOT/dev/pts" "$ROOT/proc" "$ROOT/dev" 2>/dev/null; }
unmount
if mountpoint -q "$ROOT/ccache" 2>/dev/null; then echo "fresh-check: $ROOT/ccache is still mounted"; exit 1; fi
rm -rf "$ROOT" && cp -a "$BASE" "$ROOT" || { echo "fresh-check: could not copy the base root"; exit 1; }
git clone -q "$SRC" "$ROOT/src" || { echo "fresh-check: clone failed"; exit 1; }
# the certificate authorities this machine adds to Debian's (a network that inspects TLS signs
# the npm registry's certificate with its own): a user's machine trusts its own network; the PEM
# bundle goes where Debian's ca-certificates puts its own, which Node.js and npm then read
# (and among its local ones, so that a later update-ca-certificates keeps them)
if compgen -G "/usr/local/share/ca-certificates/*.crt" >/dev/null; then
  mkdir -p "$ROOT/usr/local/share/ca-certificates"
  cp /usr/local/share/ca-certificates/*.crt "$ROOT/usr/local/share/ca-certificates/"
  cat /usr/local/share/ca-certificates/*.crt >>"$ROOT/etc/ssl/certs/ca-certificates.crt"
fi
# what the commands write is newer than this mark
touch "$ROOT/fresh-check-start"
sleep 1
mount --bind /proc "$ROOT/proc" && mount --bind /dev "$ROOT/dev" &&
  mount --bind /dev/pts "$ROOT/dev/pts" || { unmount; echo "fresh-check: mount failed"; exit 1; }
trap unmount EXIT
extra_env=()
[ -z "${PUPPET_MAIN_QUICK:-}" ] || extra_env+=("PUPPET_MAIN_QUICK=$PUPPET_MAIN_QUICK")
if [ -n "${CCACHE_STORE:-}" ]; then
  mkdir -p "$CCACHE_STORE" "$ROOT/ccache" && mount --bind "$CCACHE_STORE" "$ROOT/ccache" &&
    chroot "$ROOT" /bin/bash -c 'apt-get update -qq && apt-get install -y -qq ccache' >/tmp/fresh-ccache.log 2>&1 ||
    { echo "fresh-check: could not set up the compiler cache (log /tmp/fresh-ccache.log)"; exit 1; }
  extra_env+=(CMAKE_C_COMPILER_LAUNCHER=ccache CMAKE_CXX_COMPILER_LAUNCHER=ccache CCACHE_DIR=/ccache
    CCACHE_BASEDIR=/src CCACHE_NOHASHDIR=true CCACHE_MAXSIZE=6G CCACHE_SLOPPINESS=locale)
  echo "== compiler cache: $CCACHE_STORE"
fi

i=0
failed=0
for cmd in "$@"; do
  i=$((i + 1))
  echo "== command $i: $cmd"
  SECONDS=0
  chroot "$ROOT" /usr/bin/env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    TERM=dumb "${extra_env[@]}" /bin/bash -lc "cd /src && $cmd" </dev/null >"/tmp/fresh-cmd$i.log" 2>&1
  code=$?
  echo "   exit $code after ${SECONDS}s (log /tmp/fresh-cmd$i.log)"
  grep -m 1 '^setup: ' "/tmp/fresh-cmd$i.log" | sed 's/^/   | /'
  tail -n 8 "/tmp/fresh-cmd$i.log" | sed 's/^/   | /'
  [ $code -eq 0 ] || failed=1
done

for pattern in "${expect[@]}"; do
  found=0
  for path in "$ROOT"/src/$pattern; do
    [ -e "$path" ] || continue
    found=1
    if [ "$path" -nt "$ROOT/fresh-check-start" ]; then continue; fi
    echo "   not written by the commands: ${path#"$ROOT"/src/}"
    failed=1
  done
  [ $found -eq 1 ] || { echo "   missing: $pattern"; failed=1; }
done
[ ${#expect[@]} -eq 0 ] || [ $failed -ne 0 ] || echo "== written anew: ${expect[*]}"
exit $failed
