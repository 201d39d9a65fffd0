// SPDX-License-Identifier: MIT
#include "program/thumbnail.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "program/png.h"

namespace omnislice {

using Eigen::Vector3d;

Vector3d thumbnailViewDirection() { return Vector3d(1, -1.4, 1.1).normalized(); }

ThumbnailImage renderThumbnail(const Mesh& part, int width, int height) {
  ThumbnailImage img;
  img.width = std::clamp(width, 1, 1024);
  img.height = std::clamp(height, 1, 1024);
  img.view = thumbnailViewDirection();
  img.rgba.assign(size_t(img.width) * size_t(img.height) * 4, 0);
  if (part.empty()) return img;
  // Screen axes: right is horizontal, up is the part's +Z as seen from the view.
  const Vector3d e = img.view;
  const Vector3d right = Vector3d::UnitZ().cross(e).normalized();
  const Vector3d up = e.cross(right);
  const size_t nv = part.vertexCount();
  std::vector<Vector3d> screen(nv);  // (right, up, towards the viewer), mm
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  std::vector<uint8_t> used(nv, 0);
  for (uint32_t v : part.triangles) used[v] = 1;
  for (size_t v = 0; v < nv; ++v) {
    const Vector3d p = part.vertex(v);
    screen[v] = {p.dot(right), p.dot(up), p.dot(e)};
    if (!used[v]) continue;
    lo = lo.cwiseMin(screen[v].head<2>());
    hi = hi.cwiseMax(screen[v].head<2>());
  }
  const Eigen::Vector2d extent = (hi - lo).cwiseMax(1e-9);
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  // Supersampled: the image's pixels are averages of ss x ss samples.
  const int ss = size_t(img.width) * size_t(img.height) <= 512 * 512 ? 3 : 2;
  const int W = img.width * ss, H = img.height * ss;
  const double scale = 0.9 * std::min(W / extent.x(), H / extent.y());  // samples per mm
  img.mmPerPixel = ss / scale;
  std::vector<float> depth(size_t(W) * size_t(H), -std::numeric_limits<float>::infinity());
  std::vector<float> shade(size_t(W) * size_t(H), -1.0f);  // < 0: background
  const Vector3d light = (e + Vector3d(0.3, 0.2, 0.6)).normalized();
  const size_t nf = part.faceCount();
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &part.triangles[3 * f];
    Eigen::Vector2d s[3];
    double z[3];
    for (int k = 0; k < 3; ++k) {
      const Vector3d& q = screen[t[k]];
      s[k] = {0.5 * W + (q.x() - centre.x()) * scale, 0.5 * H - (q.y() - centre.y()) * scale};
      z[k] = q.z();
    }
    const double area = (s[1] - s[0]).x() * (s[2] - s[0]).y() - (s[1] - s[0]).y() * (s[2] - s[0]).x();
    if (!(std::abs(area) > 1e-12)) continue;  // edge-on (or not finite)
    Vector3d n = (part.vertex(t[1]) - part.vertex(t[0])).cross(part.vertex(t[2]) - part.vertex(t[0]));
    const double nn = n.norm();
    if (!(nn > 0)) continue;
    n /= nn;
    if (n.dot(e) < 0) n = -n;  // two-sided: the side facing the viewer
    const float lit = float(0.3 + 0.7 * std::max(0.0, n.dot(light)));
    const int x0 = std::max(0, int(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
    const int x1 = std::min(W - 1, int(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
    const int y0 = std::max(0, int(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
    const int y1 = std::min(H - 1, int(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d p(x + 0.5, y + 0.5);
        // Barycentric weights from the edge functions (the same sign as the area inside).
        auto edge = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
          return (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x();
        };
        const double w0 = edge(s[1], s[2]) / area, w1 = edge(s[2], s[0]) / area, w2 = edge(s[0], s[1]) / area;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const float zp = float(w0 * z[0] + w1 * z[1] + w2 * z[2]);
        const size_t k = size_t(y) * size_t(W) + size_t(x);
        if (zp > depth[k]) {
          depth[k] = zp;
          shade[k] = lit;
        }
      }
    }
  }
  // Resolve: average colour over the covered samples, alpha = the covered share.
  const double base[3] = {0x8f, 0xb3, 0xd9};  // the page's part colour
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      double sum = 0;
      int covered = 0;
      for (int j = 0; j < ss; ++j) {
        for (int i = 0; i < ss; ++i) {
          const float v = shade[size_t(y * ss + j) * size_t(W) + size_t(x * ss + i)];
          if (v < 0) continue;
          sum += v;
          ++covered;
        }
      }
      if (covered == 0) continue;
      uint8_t* px = &img.rgba[(size_t(y) * size_t(img.width) + size_t(x)) * 4];
      const double lit = sum / covered;
      for (int c = 0; c < 3; ++c) px[c] = uint8_t(std::lround(std::clamp(base[c] * lit, 0.0, 255.0)));
      px[3] = uint8_t(std::lround(255.0 * covered / (ss * ss)));
    }
  }
  return img;
}

std::string thumbnailBlock(const std::vector<uint8_t>& png, int width, int height, const std::string& prefix) {
  const std::string b64 = base64Encode(png);
  std::string out = prefix + "thumbnail begin " + std::to_string(width) + "x" + std::to_string(height) + " " +
                    std::to_string(b64.size()) + "\n";
  constexpr size_t kLine = 78;
  for (size_t i = 0; i < b64.size(); i += kLine) out += prefix + b64.substr(i, kLine) + "\n";
  out += prefix + "thumbnail end\n";
  return out;
}

ThumbnailSizes parseThumbnailSizes(const std::string& text) {
  ThumbnailSizes r;
  std::string t = text;
  for (char& c : t) {
    if (c == ',' || c == ';') c = ' ';
    if (c == 'X') c = 'x';
  }
  std::istringstream in(t);
  for (std::string item; in >> item;) {
    const size_t x = item.find('x');
    char* end = nullptr;
    const long w = x == std::string::npos ? 0 : std::strtol(item.c_str(), &end, 10);
    const bool wOk = x != std::string::npos && end == item.c_str() + x && x > 0;
    const long h = wOk ? std::strtol(item.c_str() + x + 1, &end, 10) : 0;
    const bool hOk = wOk && x + 1 < item.size() && *end == '\0';
    if (!hOk) {
      r.status = Status::InvalidOption;
      r.message = "thumbnail size '" + item.substr(0, 20) + "' is not WIDTHxHEIGHT (e.g. 220x124)";
      return r;
    }
    if (w < 1 || w > 1024 || h < 1 || h > 1024) {
      r.status = Status::InvalidOption;
      r.message = "thumbnail size " + item.substr(0, 20) + ": each side must be 1 to 1024 pixels";
      return r;
    }
    r.sizes.emplace_back(int(w), int(h));
  }
  if (r.sizes.size() > 8) {
    r.status = Status::InvalidOption;
    r.message = "at most 8 thumbnail sizes";
    r.sizes.clear();
  }
  return r;
}

}  // namespace omnislice
