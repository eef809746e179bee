#!/usr/bin/env bash
# Regenerates docs/results/: for a calm sea, an agitated sea and grazing light, under Preetham's
# sky as the paper (scenes/figure/) and under the physical sky, the default (scenes/figure/physical/,
# in docs/results/physical/), and for the default scene itself (docs/results/default/): the ground
# truth, the full method, the paper's and its constant-BRDF baseline (total, reflected sun,
# reflected sky as PNGs), the error-against-time, energy-against-distance and detail tables and
# plots (SVG), and the flicker table. About 20-25 minutes a ground truth on two cores with
# lavapipe, nearly all of the time; SCENES="figure/calm ..." runs some of them.
# Each step says what it does and where the whole stands; the ocean commands draw their own
# progress (a bar on a terminal, lines otherwise).
set -euo pipefail
cd "$(dirname "$0")/.."
W=${W:-160}; H=${H:-120}; N=${N:-12}
# The ground truths are kept here (large, not committed) and reused while their size, samples,
# scene and the ground truth's own sources are unchanged: rerunning after a change to the
# method costs minutes, not an hour.
REFERENCES=${REFERENCES:-target/reference}
read -r -a seas <<<"${SCENES:-figure/calm figure/agitated figure/grazing figure/physical/calm figure/physical/agitated figure/physical/grazing default}"
steps=$((1 + ${#seas[@]} * 5))
step=0
started=$SECONDS
say() {
    step=$((step + 1))
    echo "results.sh [$step/$steps, $((SECONDS - started)) s]: $*" >&2
}
say "building the release binary"
cargo build --release
# A copy of the binary: a rebuild while this runs (an hour and more) must not change it half way.
bin=$(mktemp -d)/ocean
cp target/release/ocean "$bin"
# What the ground truth is made of: its scene and its own sources.
sources=(glsl/groundtruth.comp glsl/groundtruth_sky.glsl glsl/atmosphere.glsl src/measure/groundtruth.rs
    src/measure/truth_sky.rs src/model/atmosphere.rs)
for sea in "${seas[@]}"; do
    scene=scenes/$sea.toml
    name=${sea#figure/}
    out=docs/results/$name
    mkdir -p "$out"
    ref=$REFERENCES/$name
    stamp="$W $H $N $(cat "$scene" "${sources[@]}" | sha256sum | cut -c1-16)"
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
            image=$method; [ "$terms" = sun,sky,sea ] || image=$method.$terms
            "$bin" render --scene "$scene" --width "$W" --height "$H" --method "$method" --terms "$terms" \
                --out "$out/$image.png" >/dev/null
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
