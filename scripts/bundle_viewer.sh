#!/usr/bin/env bash
# Bundles three.js (from the npm registry, versions pinned in scripts/viewer/package.json) into
# assets/viewer/three-bundle.js, the script `holoc view` embeds in its page (include_str!), and
# copies three.js's licence beside it. Run it again after changing the versions; commit both files.
# Needs node and npm. The packages go into a scratch folder, never into the repository.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp "$root/scripts/viewer/package.json" "$root/scripts/viewer/entry.js" "$work/"
cd "$work"
npm install --no-audit --no-fund --loglevel=error >/dev/null
version="$(node -p 'JSON.parse(require("fs").readFileSync("node_modules/three/package.json")).version')"
mkdir -p "$root/assets/viewer"
{
  echo "/* three.js ${version} (https://threejs.org, MIT licence: assets/viewer/LICENSE-three.txt),"
  echo "   bundled by scripts/bundle_viewer.sh for holoc view. Do not edit by hand. */"
  npx --no-install esbuild entry.js --bundle --minify --format=iife --global-name=HOLOC3D \
    --legal-comments=none --target=es2020 --log-level=warning
} >"$root/assets/viewer/three-bundle.js"
cp node_modules/three/LICENSE "$root/assets/viewer/LICENSE-three.txt"
echo "assets/viewer/three-bundle.js: three $version, $(wc -c <"$root/assets/viewer/three-bundle.js") bytes"
