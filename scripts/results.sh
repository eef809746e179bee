#!/usr/bin/env bash
# Regenerates docs/results/: for a calm sea, an agitated sea and grazing light, the ground truth,
# the full method, the paper's and its constant-BRDF baseline (total, reflected sun, reflected sky
# as PNGs), the error-against-time and energy-against-distance tables and plots (SVG), and the
# flicker table. About 80 minutes on two cores with lavapipe (measured last: 78, with other work
# sharing the cores for part of it), nearly all of it the three ground truths.
# Each step says what it does and where the whole stands; the ocean commands draw their own
# progress (a bar on a terminal, lines otherwise).
set -euo pipefail
cd "$(dirname "$0")/.."
W=${W:-160}; H=${H:-120}; N=${N:-12}
# The ground truths are kept here (large, not committed) and reused while their size, samples,
# scene and the ground truth's own sources are unchanged: rerunning after a change to the
# method costs minutes, not an hour.
REFERENCES=${REFERENCES:-target/reference}
seas=(calm agitated grazing)
steps=$((1 + ${#seas[@]} * 5))
step=0
started=$SECONDS
say() {
    step=$((step + 1))
    echo "results.sh [$step/$steps, $((SECONDS - started)) s]: $*" >&2
}
say "building the release binary"
cargo build --release
bin=target/release/ocean
for sea in "${seas[@]}"; do
    out=docs/results/$sea
    mkdir -p "$out"
    scene=scenes/figure/$sea.toml
    ref=$REFERENCES/$sea
    stamp="$W $H $N $(cat "$scene" glsl/groundtruth.comp src/measure/groundtruth.rs | sha256sum | cut -c1-16)"
    if [ -f "$ref/reference.exr" ] && [ "$(cat "$ref/stamp" 2>/dev/null)" = "$stamp" ]; then
        say "$sea: ground truth ${W}x${H}, ${N}x${N} samples per pixel: reusing $ref"
    else
        say "$sea: ground truth ${W}x${H}, ${N}x${N} samples per pixel (the longest step)"
        mkdir -p "$ref"
        rm -f "$ref/stamp"
        "$bin" reference --scene "$scene" --width "$W" --height "$H" --samples "$N" \
            --out "$ref/reference.exr" --png "$ref/reference.png" --report "$ref/reference.json"
        echo "$stamp" >"$ref/stamp"
    fi
    cp "$ref"/reference*.png "$ref/reference.json" "$ref/reference.exr.json" "$out/"
    say "$sea: the full method, the paper's and its baseline, total and per term (9 renders)"
    for method in full paper constant-brdf; do
        for terms in sun,sky,sea sun sky; do
            name=$method; [ "$terms" = sun,sky,sea ] || name=$method.$terms
            "$bin" render --scene "$scene" --width "$W" --height "$H" --method "$method" --terms "$terms" \
                --out "$out/$name.png" >/dev/null
        done
    done
    say "$sea: error against time, every method and setting"
    "$bin" bench error-vs-time --scene "$scene" --reference "$ref/reference.exr" --out "$out" --frames 20
    say "$sea: where the sky's error comes from: the model's quadrature, the lookup, the sea's own masking"
    "$bin" bench sky-model --scene "$scene" --reference "$ref/reference.exr" --out "$out"
    say "$sea: flicker over a second at 30 frames per second, every method"
    "$bin" bench flicker --scene "$scene" --width "$W" --height "$H" --frames 30 --out "$out"
done
echo "results.sh: done in $((SECONDS - started)) s; docs/results/ regenerated" >&2
