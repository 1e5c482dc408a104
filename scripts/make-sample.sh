#!/usr/bin/env bash
# Regenerates the project's sample recording in rawlogs/ (the README's embedded default):
# 200 frames (6.7 s) of the synthetic walking_xyz preset at 320x240, seed 1, JPEG colour, depth
# as MRPT range images (re-gzipped at level 9), ground truth beside it. About 9 MB.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/bin/smap-synth ] || bash scripts/build.sh
name=sample_walking_xyz
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
build/bin/smap-synth --preset walking_xyz --frames 200 --seed 1 --size 320x240 --jpeg-quality 70 \
    --contact-sheet 0 --out "$work/seq"
for f in "$work"/seq/sequence_Images/depth/*.bin; do
    gzip -dc < "$f" | gzip -9n > "$f.tmp" && mv "$f.tmp" "$f"
done
rm -rf "rawlogs/${name}.rawlog" "rawlogs/${name}_Images" "rawlogs/${name}_groundtruth.txt" "rawlogs/${name}_gt"
mv "$work/seq/sequence.rawlog" "rawlogs/${name}.rawlog"
mv "$work/seq/sequence_Images" "rawlogs/${name}_Images"
# A fixed first comment line (the converter names its temporary source folder there).
sed '1s|.*|# ground truth of the synthetic walking_xyz sample (smap-synth, seed 1)|' \
    "$work/seq/sequence_groundtruth.txt" > "rawlogs/${name}_groundtruth.txt"
mkdir -p "rawlogs/${name}_gt"
mv "$work"/seq/{labels,instances,dynamic,objects,meta.json} "rawlogs/${name}_gt/"
du -sh "rawlogs/${name}"* | sed 's/^/make-sample: /'
