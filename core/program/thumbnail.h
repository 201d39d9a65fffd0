// SPDX-License-Identifier: MIT
// Thumbnails of the part for printer hosts (OctoPrint, Moonraker, Prusa printers): the part as
// placed, drawn by a small z-buffer rasteriser (orthographic, seen from the front right above,
// shaded, 3x3 supersampled, transparent background), PNG-encoded (program/png.h) and written into
// G-code as PrusaSlicer's comment block:
//   ; thumbnail begin WxH LEN        (LEN: characters of base64)
//   ; <up to 78 base64 characters>
//   ; thumbnail end
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

struct ThumbnailImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // 4 bytes per pixel, rows top to bottom; alpha 0 off the part
  double mmPerPixel = 0;      // the projection's scale
  Eigen::Vector3d view{0, 0, 1};  // unit, from the part towards the viewer (orthographic)
};

// The view: from the front right above, as a slicer's default view.
Eigen::Vector3d thumbnailViewDirection();

// The part drawn into width x height pixels (each in [1, 1024]), scaled so its projection fills
// 90 % of the image in its tighter direction and centred. An empty mesh gives a clear image.
ThumbnailImage renderThumbnail(const Mesh& part, int width, int height);

// PrusaSlicer's G-code block of a PNG, each line starting with `prefix` ("; ").
std::string thumbnailBlock(const std::vector<uint8_t>& png, int width, int height, const std::string& prefix);

// Thumbnail sizes "WxH[,WxH...]" (e.g. "16x16,220x124"; spaces allowed; empty = none): each side
// in [1, 1024], at most 8. InvalidOption naming the problem.
struct ThumbnailSizes : Outcome {
  std::vector<std::pair<int, int>> sizes;
};
ThumbnailSizes parseThumbnailSizes(const std::string& text);

}  // namespace omnislice
