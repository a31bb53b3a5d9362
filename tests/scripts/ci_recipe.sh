#!/bin/sh
# The CI recipe of book/src/scenes-under-test.md with the real `cargo install` (run by hand; the
# CI runs `cargo test --test ci_recipe`, which puts the holoc it built on PATH instead, since a
# release compile takes minutes).
#
#   tests/scripts/ci_recipe.sh [--path]
#
# Installs holoc with the page's own install line into a temporary CARGO_INSTALL_ROOT, with
# HOLOC_GIT set to a file:// URL of this checkout (cargo clones a local git repository as it
# would a remote one: what is committed is what is installed), or, with --path, with the
# line's `--git "$HOLOC_GIT"` replaced by `--path <this checkout>`. Then it runs the recipe's
# test with the installed binary (HOLOC_CI_RECIPE_BIN). Cargo refuses a git source, even a
# file:// one, in offline mode, so CARGO_NET_OFFLINE is left as it is (with --path, set it to
# true to install without a network); the checkout's target/ is reused for the
# dependencies already compiled (CARGO_TARGET_DIR; set it to another folder to build afresh).
set -eu
checkout=$(cd "$(dirname "$0")/../.." && pwd)
page="$checkout/book/src/scenes-under-test.md"
line=$(grep -m1 -- '- run: cargo install' "$page" | sed 's/.*- run: //; s/ # .*//')
[ -n "$line" ] || { echo "no install line in $page" >&2; exit 1; }
if [ "${1:-}" = "--path" ]; then
    line=$(printf '%s\n' "$line" | sed "s|--git \"\$HOLOC_GIT\"|--path \"$checkout\"|")
fi
root=$(mktemp -d "${TMPDIR:-/tmp}/holoc-install.XXXXXX")
trap 'rm -rf "$root"' EXIT
export CARGO_INSTALL_ROOT="$root"
export HOLOC_GIT="file://$checkout"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$checkout/target}"
echo "+ $line   (HOLOC_GIT=$HOLOC_GIT, CARGO_INSTALL_ROOT=$root)"
sh -c "$line"
"$root/bin/holoc" --version
cd "$checkout"
HOLOC_CI_RECIPE_BIN="$root/bin/holoc" cargo test --test ci_recipe
