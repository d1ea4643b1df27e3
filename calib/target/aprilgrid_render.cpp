#include "calib/target/aprilgrid_render.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "calib/target/tag36h11.h"
#include "calib/text_format.h"
#include "data/formats/atomic_file.h"

namespace adugs::calib {
namespace {

constexpr double kPointsPerMetre = 72.0 / 0.0254;
constexpr double kCaptionHeightM = 0.008;  // caption text height when the margin allows it

void addTag(const AprilGrid& g, int id, std::vector<Rect2d>& out) {
  const double x0 = g.tagCol(id) * g.pitch();
  const double y0 = g.tagRow(id) * g.pitch();
  const double s = g.tag_size_m;
  const int cells = 6 + 2 * g.border_bits;
  const double bit = s / cells;
  const double b = g.border_bits * bit;
  // Border as four strips.
  out.push_back({x0, y0, x0 + s, y0 + b});
  out.push_back({x0, y0 + s - b, x0 + s, y0 + s});
  out.push_back({x0, y0 + b, x0 + b, y0 + s - b});
  out.push_back({x0 + s - b, y0 + b, x0 + s, y0 + s - b});
  // Data bits; runs of black cells in a row become one rectangle (no seams in PDF viewers).
  const Tag36h11Bits bits = tag36h11Bits(id);
  for (int row = 0; row < 6; ++row) {
    const double top = y0 + s - b - row * bit;  // row 0 is the top row of the upright tag
    int col = 0;
    while (col < 6) {
      if (bits[row][col]) {
        ++col;
        continue;
      }
      int end = col;
      while (end < 6 && !bits[row][end]) ++end;
      out.push_back({x0 + b + col * bit, top - bit, x0 + b + end * bit, top});
      col = end;
    }
  }
}

// Escapes a PDF literal string.
std::string pdfString(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '(' || c == ')' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

TargetLayout aprilGridLayout(const AprilGrid& grid, double margin_m) {
  grid.validate();
  if (!(margin_m >= 0) || !std::isfinite(margin_m))
    throw std::invalid_argument("margin must be a non-negative number of metres");
  TargetLayout layout;
  for (int id = 0; id < grid.numTags(); ++id) addTag(grid, id, layout.black);
  // One square in each gap between tag corners, including the outer ones (as Kalibr draws).
  const double gap = grid.tag_spacing * grid.tag_size_m;
  if (gap > 0) {
    for (int j = 0; j <= grid.tag_rows; ++j)
      for (int i = 0; i <= grid.tag_cols; ++i)
        layout.black.push_back(
            {i * grid.pitch() - gap, j * grid.pitch() - gap, i * grid.pitch(), j * grid.pitch()});
  }
  const double black_max_x = (grid.tag_cols - 1) * grid.pitch() + grid.tag_size_m + gap;
  const double black_max_y = (grid.tag_rows - 1) * grid.pitch() + grid.tag_size_m + gap;
  layout.min_x = -gap - margin_m;
  layout.min_y = -gap - margin_m;
  layout.max_x = black_max_x + margin_m;
  layout.max_y = black_max_y + margin_m;
  if (margin_m >= 1.5 * kCaptionHeightM) {
    layout.caption_x = -gap;
    layout.caption_y = layout.min_y + (margin_m - 0.6 * kCaptionHeightM) / 2;
    layout.caption = strprintf(
        "AprilGrid tag36h11 %dx%d, tag %.1f mm, spacing %.3g (%.1f mm), border %d bit%s; "
        "tag 0 bottom-left, x right, y up",
        grid.tag_rows, grid.tag_cols, grid.tag_size_m * 1000, grid.tag_spacing, gap * 1000,
        grid.border_bits, grid.border_bits == 1 ? "" : "s");
  }
  return layout;
}

RenderedTarget renderAprilGridPxPerM(const AprilGrid& grid, double px_per_m, double margin_m) {
  if (!(px_per_m > 0) || !std::isfinite(px_per_m))
    throw std::invalid_argument("resolution must be positive");
  const TargetLayout layout = aprilGridLayout(grid, margin_m);
  RenderedTarget r;
  r.px_per_m = px_per_m;
  r.min_x = layout.min_x;
  r.max_y = layout.max_y;
  const int width = static_cast<int>(std::lround((layout.max_x - layout.min_x) * px_per_m));
  const int height = static_cast<int>(std::lround((layout.max_y - layout.min_y) * px_per_m));
  if (width < 1 || height < 1 || double(width) * height > 4.0e8)
    throw std::invalid_argument("target raster of " + std::to_string(width) + "x" +
                                std::to_string(height) + " pixels is out of range");
  r.image = cv::Mat(height, width, CV_8UC1, cv::Scalar(255));
  // Rectangles cover the pixels whose centres fall inside them.
  for (const Rect2d& rect : layout.black) {
    const int u0 = static_cast<int>(std::lround((rect.x0 - layout.min_x) * px_per_m));
    const int u1 = static_cast<int>(std::lround((rect.x1 - layout.min_x) * px_per_m));
    const int v0 = static_cast<int>(std::lround((layout.max_y - rect.y1) * px_per_m));
    const int v1 = static_cast<int>(std::lround((layout.max_y - rect.y0) * px_per_m));
    const cv::Rect box = cv::Rect(u0, v0, u1 - u0, v1 - v0) & cv::Rect(0, 0, width, height);
    if (box.area() > 0) r.image(box).setTo(0);
  }
  if (!layout.caption.empty()) {
    // Hershey simplex capitals are about 22 px high at scale 1.
    const double scale = kCaptionHeightM * 0.6 * px_per_m / 22.0;
    const int thickness = std::max(1, static_cast<int>(std::lround(scale * 1.6)));
    const Eigen::Vector3d at(layout.caption_x, layout.caption_y, 0);
    const Eigen::Vector2d px = r.pixelOf(at);
    cv::putText(r.image, layout.caption, cv::Point(int(px.x()), int(px.y())),
                cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0), thickness, cv::LINE_8);
  }
  return r;
}

RenderedTarget renderAprilGrid(const AprilGrid& grid, double dpi, double margin_m) {
  if (!(dpi > 0) || !std::isfinite(dpi)) throw std::invalid_argument("dpi must be positive");
  return renderAprilGridPxPerM(grid, dpi / 0.0254, margin_m);
}

std::string aprilGridPdf(const TargetLayout& layout) {
  auto pt = [](double metres) { return strprintf("%.3f", metres * kPointsPerMetre); };
  std::ostringstream content;
  content << "0 g\n";
  for (const Rect2d& r : layout.black)
    content << pt(r.x0 - layout.min_x) << ' ' << pt(r.y0 - layout.min_y) << ' '
            << pt(r.x1 - r.x0) << ' ' << pt(r.y1 - r.y0) << " re\n";
  content << "f\n";
  if (!layout.caption.empty()) {
    content << "BT /F1 " << pt(kCaptionHeightM * 0.8) << " Tf " << pt(layout.caption_x - layout.min_x)
            << ' ' << pt(layout.caption_y - layout.min_y) << " Td (" << pdfString(layout.caption)
            << ") Tj ET\n";
  }
  const std::string stream = content.str();
  const std::string width = pt(layout.max_x - layout.min_x);
  const std::string height = pt(layout.max_y - layout.min_y);

  // A minimal PDF 1.4: catalog, page tree, one page, its content stream and a standard font.
  std::vector<std::string> objects = {
      "<< /Type /Catalog /Pages 2 0 R >>",
      "<< /Type /Pages /Kids [3 0 R] /Count 1 >>",
      "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " + width + " " + height +
          "] /Contents 4 0 R /Resources << /Font << /F1 5 0 R >> >> >>",
      "<< /Length " + std::to_string(stream.size()) + " >>\nstream\n" + stream + "endstream",
      "<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica >>"};
  std::string pdf = "%PDF-1.4\n";
  std::vector<size_t> offsets;
  for (size_t i = 0; i < objects.size(); ++i) {
    offsets.push_back(pdf.size());
    pdf += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
  }
  const size_t xref = pdf.size();
  pdf += "xref\n0 " + std::to_string(objects.size() + 1) + "\n0000000000 65535 f \n";
  for (size_t off : offsets) pdf += strprintf("%010zu 00000 n \n", off);
  pdf += "trailer\n<< /Size " + std::to_string(objects.size() + 1) +
         " /Root 1 0 R >>\nstartxref\n" + std::to_string(xref) + "\n%%EOF\n";
  return pdf;
}

void writeAprilGridPdf(const std::string& path, const AprilGrid& grid, double margin_m) {
  data::writeTextFileAtomically(path, aprilGridPdf(aprilGridLayout(grid, margin_m)));
}

}  // namespace adugs::calib
