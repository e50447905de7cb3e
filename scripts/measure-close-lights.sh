#!/usr/bin/env bash
# Pixels next to close lights (docs/noise-and-bias.md, "Pixels next to close lights"): the
# many-light scene with direct light only, RIS and ReSTIR with power-proportional candidates and
# ReSTIR with light-BVH candidates, 16 frames each from SEEDS seeds (3, 4, ...); then, for the
# eight pixels with the largest error in RIS's first run, the mean and median over the seeds of
# each pixel's 16-frame mean against the path-traced reference, and each method's 16-frame MSE.
# Needs python3 (standard library only). Work files: out/close-lights-LIGHTS/.
# Usage: scripts/measure-close-lights.sh [LIGHTS SEEDS REFERENCE_SPP]  (default 100000 23 1024)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

lights=${1:-100000} seeds=${2:-23} reference_spp=${3:-1024}
bash scripts/render.sh --width 8 --height 8 --frames 1 --out out/warm-up.png >/dev/null
render=build/render/examples/pathtracer/restir-render
dir=out/close-lights-$lights
mkdir -p "$dir"
common=(--scene many-lights --lights "$lights" --gi none --width 640 --height 360)
[ -f "$dir/reference.pfm" ] || "$render" "${common[@]}" --method reference --seed 1 \
  --spp "$reference_spp" --frames 1 --out "$dir/reference.pfm" >/dev/null
for ((seed = 3; seed < 3 + seeds; ++seed)); do
  "$render" "${common[@]}" --method ris --source power --candidates 32 --frames 16 \
    --seed "$seed" --out "$dir/ris-$seed.pfm" >/dev/null
  "$render" "${common[@]}" --method restir --source power --candidates 32 --frames 16 \
    --seed "$seed" --out "$dir/restir-$seed.pfm" >/dev/null
  "$render" "${common[@]}" --method restir --source bvh --candidates 4 --frames 16 \
    --seed "$seed" --out "$dir/bvh-$seed.pfm" >/dev/null
done

python3 - "$dir" "$seeds" <<'PYTHON'
import array, statistics, sys

directory, seed_count = sys.argv[1], int(sys.argv[2])

def read_pfm(path):  # width, height, RGB floats with rows bottom to top
    with open(path, 'rb') as f:
        f.readline()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = array.array('f')
        data.frombytes(f.read())
    if scale > 0:
        data.byteswap()
    return width, height, data

def grey(image, i):
    return (image[3 * i] + image[3 * i + 1] + image[3 * i + 2]) / 3.0

width, height, reference = read_pfm(f'{directory}/reference.pfm')
pixels = width * height
seeds = range(3, 3 + seed_count)
methods = {'RIS (power, 32)': 'ris', 'ReSTIR (power, 32)': 'restir', 'ReSTIR (bvh, 4)': 'bvh'}
images = {name: [read_pfm(f'{directory}/{stem}-{s}.pfm')[2] for s in seeds]
          for name, stem in methods.items()}
first = images['RIS (power, 32)'][0]
worst = sorted(range(pixels), key=lambda i: -(grey(first, i) - grey(reference, i)) ** 2)[:8]
print('pixel (x, y), reference, then per method the mean / median over the seeds')
sums = {name: 0.0 for name in images}
for i in worst:
    x, y = i % width, height - 1 - i // width
    row = [f'{x}, {y}', f'{grey(reference, i):.3f}']
    for name, runs in images.items():
        values = [grey(run, i) for run in runs]
        sums[name] += statistics.mean(values)
        row.append(f'{statistics.mean(values):.3f} / {statistics.median(values):.3f}')
    print(' | '.join(row))
total = sum(grey(reference, i) for i in worst)
print(f'sum: reference {total:.3f}; ' +
      '; '.join(f'{name} {value:.3f} ({100 * value / total:.0f} %)' for name, value in sums.items()))
for name, runs in images.items():
    errors = [sum((grey(run, i) - grey(reference, i)) ** 2 for i in range(pixels)) / pixels
              for run in runs]
    print(f'{name}: MSE of a 16-frame image, mean {statistics.mean(errors):.4g}, '
          f'median {statistics.median(errors):.4g}')
PYTHON
