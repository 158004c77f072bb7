#include "svg_chart.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace ctsfleet_bench {

namespace {

constexpr double kWidth = 640, kHeight = 400, kLeft = 70, kRight = 20, kTop = 40, kBottom = 50;

std::string number(double value) {
  std::ostringstream out;
  if (std::fabs(value) >= 1000 || value == std::floor(value)) {
    out << static_cast<long long>(std::llround(value));
  } else {
    out.precision(3);
    out << value;
  }
  return out.str();
}

}  // namespace

std::string line_chart(const std::string& title, const std::string& x_label, const std::string& y_label,
                       const std::vector<Series>& series) {
  double x_min = std::numeric_limits<double>::max(), x_max = std::numeric_limits<double>::lowest();
  double y_min = x_min, y_max = x_max;
  for (const Series& s : series) {
    for (auto [x, y] : s.points) {
      x_min = std::min(x_min, x), x_max = std::max(x_max, x);
      y_min = std::min(y_min, y), y_max = std::max(y_max, y);
    }
  }
  if (x_min > x_max) x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  x_min = std::min(x_min, 0.0);  // time and counts start at zero
  if (x_max == x_min) x_max = x_min + 1;
  const double pad = (y_max - y_min) * 0.05 + 1e-9;
  y_min -= pad, y_max += pad;
  const auto px = [&](double x) { return kLeft + (x - x_min) / (x_max - x_min) * (kWidth - kLeft - kRight); };
  const auto py = [&](double y) { return kHeight - kBottom - (y - y_min) / (y_max - y_min) * (kHeight - kTop - kBottom); };

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg << "<text x=\"" << kWidth / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << title << "</text>\n";
  svg << "<line x1=\"" << kLeft << "\" y1=\"" << kHeight - kBottom << "\" x2=\"" << kWidth - kRight << "\" y2=\""
      << kHeight - kBottom << "\" stroke=\"black\"/>\n";
  svg << "<line x1=\"" << kLeft << "\" y1=\"" << kTop << "\" x2=\"" << kLeft << "\" y2=\"" << kHeight - kBottom
      << "\" stroke=\"black\"/>\n";
  for (int i = 0; i <= 5; ++i) {
    const double x = x_min + (x_max - x_min) * i / 5, y = y_min + (y_max - y_min) * i / 5;
    svg << "<text x=\"" << px(x) << "\" y=\"" << kHeight - kBottom + 16 << "\" text-anchor=\"middle\">" << number(x)
        << "</text>\n";
    svg << "<text x=\"" << kLeft - 6 << "\" y=\"" << py(y) + 4 << "\" text-anchor=\"end\">" << number(y) << "</text>\n";
    svg << "<line x1=\"" << kLeft << "\" y1=\"" << py(y) << "\" x2=\"" << kWidth - kRight << "\" y2=\"" << py(y)
        << "\" stroke=\"#ddd\"/>\n";
  }
  svg << "<text x=\"" << (kLeft + kWidth - kRight) / 2 << "\" y=\"" << kHeight - 12 << "\" text-anchor=\"middle\">"
      << x_label << "</text>\n";
  svg << "<text transform=\"translate(16," << (kTop + kHeight - kBottom) / 2
      << ") rotate(-90)\" text-anchor=\"middle\">" << y_label << "</text>\n";
  for (size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    svg << "<polyline fill=\"none\" stroke-width=\"2\" stroke=\"" << s.colour << "\" points=\"";
    for (size_t i = 0; i < s.points.size(); ++i) {
      if (s.steps && i > 0) svg << px(s.points[i].first) << "," << py(s.points[i - 1].second) << " ";
      svg << px(s.points[i].first) << "," << py(s.points[i].second) << " ";
    }
    svg << "\"/>\n";
    for (auto [x, y] : s.points) {
      svg << "<circle cx=\"" << px(x) << "\" cy=\"" << py(y) << "\" r=\"2.5\" fill=\"" << s.colour << "\"/>\n";
    }
    const double ly = kTop + 8 + 18 * k;
    svg << "<line x1=\"" << kWidth - kRight - 170 << "\" y1=\"" << ly << "\" x2=\"" << kWidth - kRight - 150
        << "\" y2=\"" << ly << "\" stroke=\"" << s.colour << "\" stroke-width=\"3\"/>\n";
    svg << "<text x=\"" << kWidth - kRight - 144 << "\" y=\"" << ly + 4 << "\">" << s.name << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace ctsfleet_bench
