#!/usr/bin/env bash
# Makes ZABAGED-style XYZ point files ("easting northing altitude" per line) from an SRTM tile
# with GDAL's own tools, so that the XYZ path of roadcross-build can be checked against the
# raster path on the same terrain. The result is DERIVED FROM SRTM, not real ČÚZK ZABAGED/DMR
# data (maps/zabaged/ holds a real DMR 5G sample).
#
#   scripts/make-derived-xyz.sh RASTER CRS "XMIN YMIN XMAX YMAX" CELL_M SEPARATOR OUT
#
# RASTER   the source DEM (e.g. maps/prague/N50E014.hgt)
# CRS      target CRS of the points (EPSG:5514 for S-JTSK, EPSG:32632, ...)
# BOX      extent in the target CRS
# CELL_M   point spacing, metres
# SEPARATOR  "space" or "comma"
# OUT      the XYZ file to write (with a header line "X Y Z"; nodata cells are left out)
#
# Example (what tests/cli/terrain_real_map_test.sh runs for Prague):
#   scripts/make-derived-xyz.sh maps/prague/N50E014.hgt EPSG:5514 \
#     "-745000 -1046000 -741000 -1042500" 30 space /tmp/prague_sjtsk.xyz
set -euo pipefail
if [[ $# -ne 6 ]]; then
  sed -n '2,20p' "$0" >&2
  exit 2
fi
raster=$1 crs=$2 box=$3 cell=$4 separator=$5 out=$6
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# shellcheck disable=SC2086
gdalwarp -q -overwrite -ot Float32 -t_srs "$crs" -te $box -tr "$cell" "$cell" -r bilinear \
  -dstnodata -32768 "$raster" "$work/warped.tif"
case $separator in
  space) sep_option=() ;;
  comma) sep_option=(-co COLUMN_SEPARATOR=,) ;;
  *) echo "separator must be space or comma" >&2; exit 2 ;;
esac
gdal_translate -q -of XYZ -co ADD_HEADER_LINE=YES "${sep_option[@]}" "$work/warped.tif" \
  "$work/points.xyz"
# The XYZ driver writes every cell; drop the nodata ones as ČÚZK files have no such lines.
awk -F'[ ,]' 'NR == 1 || $3 != -32768' "$work/points.xyz" > "$out"
echo "$out: $(($(wc -l < "$out") - 1)) points derived from $(basename "$raster") in $crs" >&2
