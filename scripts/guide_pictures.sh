#!/usr/bin/env bash
# Makes the pictures of docs/guide.md from the built-in example, with the
# foldfill in build/ (bash scripts/setup.sh builds it).
set -euo pipefail
cd "$(dirname "$0")/.."
foldfill=${FOLDFILL:-build/foldfill}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=docs/pictures
mkdir -p "$out"
view=(--width 360 --height 320 --elevation 10 --azimuth 20)

"$foldfill" demo "$work/demo" --quiet
in=$work/demo/input.obj
"$foldfill" fill "$in" -o "$work/default.obj" --quiet
"$foldfill" fill "$in" -o "$work/stiff.obj" --lambda 0.05 --quiet
"$foldfill" fill "$in" -o "$work/limp.obj" --lambda 0 --quiet
"$foldfill" fill "$in" -o "$work/dense.obj" --density 2 --quiet
"$foldfill" fill "$in" -o "$work/liepa.obj" --method liepa --quiet

"$foldfill" render "$in" "$work/default.obj" -o "$out/first_fill.png" "${view[@]}"
"$foldfill" render "$in" "$work/limp.obj" "$work/default.obj" "$work/stiff.obj" -o "$out/lambda.png" "${view[@]}"
"$foldfill" render "$in" "$work/default.obj" "$work/dense.obj" -o "$out/density.png" "${view[@]}"
"$foldfill" render "$in" "$work/default.obj" "$work/liepa.obj" -o "$out/liepa.png" "${view[@]}"
echo "guide_pictures: wrote $out/{first_fill,lambda,density,liepa}.png"

# The picture of `serve` is the browser test's (tests/browser/serve.test.mjs):
# the demo filled with a plane obstacle and the Liepa comparison, a patch point
# dragged with the edit tool.
if [ -d node_modules/puppeteer-core ] && [ -x /usr/bin/chromium ]; then
  node tests/browser/serve.test.mjs "$foldfill" "$work/serve" > /dev/null
  cp "$work/serve/serve-edited.png" "$out/serve.png"
  echo "guide_pictures: wrote $out/serve.png"
fi
