// The report as a PDF, laid out with cairo's PDF surface (cairographics.org): A4 portrait sheets,
// DejaVu Sans through fontconfig, text and rules as vectors, pictures embedded losslessly.
// A table whose columns are wider than the sheet is set in a smaller type (down to 5 pt), a long
// one continues on the next sheet under its header.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <cairo-pdf.h>
#include <cairo.h>

#include "lambert/core/atomic_file.h"
#include "lambert/design/report.h"

namespace lambert {
namespace {

constexpr double kPageWidth = 595.28, kPageHeight = 841.89, kMargin = 48;  // A4 in points
constexpr double kBodySize = 9, kTitleSize = 16, kHeadingSize = 11;
constexpr const char* kFont = "DejaVu Sans";

struct Sheet {
  cairo_t* cr;
  const LightingReport& report;
  double y = kMargin;
  int sheets = 1;

  void font(double size, bool bold = false) {
    cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
  }
  double width(const std::string& text) {
    cairo_text_extents_t e;
    cairo_text_extents(cr, text.c_str(), &e);
    return e.x_advance;
  }
  void text(double x, double baseline, const std::string& s) {
    cairo_move_to(cr, x, baseline);
    cairo_show_text(cr, s.c_str());
  }
  void footer() {
    font(7);
    cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
    const std::string s = report.title + " — sheet " + std::to_string(sheets);
    text(kMargin, kPageHeight - kMargin / 2, s);
    cairo_set_source_rgb(cr, 0, 0, 0);
  }
  void newSheet() {
    footer();
    cairo_show_page(cr);
    ++sheets;
    y = kMargin;
  }
  // Room for `height` more points on this sheet, else a new one.
  void need(double height) {
    if (y + height > kPageHeight - kMargin) newSheet();
  }
  // A paragraph wrapped at word boundaries to the text width.
  void paragraph(const std::string& s, double size) {
    font(size);
    const double lineHeight = size * 1.35, maxWidth = kPageWidth - 2 * kMargin;
    std::string line;
    std::size_t start = 0;
    auto flush = [&] {
      need(lineHeight);
      y += lineHeight;
      text(kMargin, y - size * 0.3, line);
      line.clear();
    };
    while (start < s.size()) {
      std::size_t end = s.find(' ', start);
      if (end == std::string::npos) end = s.size();
      const std::string word = s.substr(start, end - start);
      const std::string candidate = line.empty() ? word : line + " " + word;
      if (!line.empty() && width(candidate) > maxWidth) {
        flush();
        line = word;
      } else {
        line = candidate;
      }
      start = end + 1;
    }
    if (!line.empty()) flush();
    y += size * 0.6;
  }
  void table(const ReportTable& t) {
    const double maxWidth = kPageWidth - 2 * kMargin, pad = 3;
    // The type size at which the widest cell of each column fits the sheet.
    auto columnWidths = [&](double size) {
      font(size, true);  // the header is set in bold
      std::vector<double> widths(t.header.size(), 0);
      for (std::size_t c = 0; c < t.header.size(); ++c) widths[c] = width(t.header[c]) + 2 * pad;
      font(size);
      for (const auto& row : t.rows)
        for (std::size_t c = 0; c < row.size() && c < widths.size(); ++c) widths[c] = std::max(widths[c], width(row[c]) + 2 * pad);
      return widths;
    };
    double size = kBodySize;
    std::vector<double> widths = columnWidths(size);
    auto total = [&] {
      double sum = 0;
      for (double w : widths) sum += w;
      return sum;
    };
    while (total() > maxWidth && size > 5) widths = columnWidths(size -= 0.5);
    const double rowHeight = size * 1.55;
    paragraphCaption(t.caption);
    auto drawRow = [&](const std::vector<std::string>& cells, bool header) {
      need(rowHeight);
      double x = kMargin;
      if (header) {
        cairo_set_source_rgb(cr, 0.92, 0.92, 0.92);
        cairo_rectangle(cr, kMargin, y, std::min(total(), maxWidth), rowHeight);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
      }
      font(size, header);
      for (std::size_t c = 0; c < cells.size() && c < widths.size(); ++c) {
        // The first column left, the others right, as figures are read.
        const double w = width(cells[c]);
        text(c == 0 ? x + pad : x + widths[c] - pad - w, y + rowHeight - size * 0.45, cells[c]);
        x += widths[c];
      }
      cairo_set_line_width(cr, 0.3);
      cairo_move_to(cr, kMargin, y + rowHeight);
      cairo_line_to(cr, kMargin + std::min(total(), maxWidth), y + rowHeight);
      cairo_stroke(cr);
      y += rowHeight;
    };
    drawRow(t.header, true);
    for (const auto& row : t.rows) {
      if (y + rowHeight > kPageHeight - kMargin) {
        newSheet();
        drawRow(t.header, true);
      }
      drawRow(row, false);
    }
    y += rowHeight;
  }
  void paragraphCaption(const std::string& caption) {
    if (caption.empty()) return;
    need(kBodySize * 4);
    font(kBodySize, true);
    y += kBodySize * 1.4;
    text(kMargin, y - kBodySize * 0.3, caption);
    y += kBodySize * 0.3;
  }
  void image(const ReportImage& picture) {
    const double maxWidth = kPageWidth - 2 * kMargin, maxHeight = 0.55 * (kPageHeight - 2 * kMargin);
    const double scale = std::min({maxWidth / picture.width, maxHeight / picture.height, 1.0});
    need(picture.height * scale + 8);
    cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, picture.width, picture.height);
    cairo_surface_flush(surface);
    unsigned char* data = cairo_image_surface_get_data(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    for (int row = 0; row < picture.height; ++row)
      for (int col = 0; col < picture.width; ++col) {
        const std::uint8_t* p = picture.rgb.data() + (static_cast<std::size_t>(row) * picture.width + col) * 3;
        std::uint32_t* q = reinterpret_cast<std::uint32_t*>(data + row * stride) + col;
        *q = (std::uint32_t{p[0]} << 16) | (std::uint32_t{p[1]} << 8) | p[2];
      }
    cairo_surface_mark_dirty(surface);
    cairo_save(cr);
    cairo_translate(cr, kMargin, y);
    cairo_scale(cr, scale, scale);
    cairo_set_source_surface(cr, surface, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_GOOD);
    cairo_paint(cr);
    cairo_restore(cr);
    cairo_surface_destroy(surface);
    y += picture.height * scale + 8;
  }
  void histogram(const ReportHistogram& h) {
    const double w = 300, height = 110, left = kMargin + 30;
    need(height + 30);
    const int bins = static_cast<int>(h.counts.size());
    const int most = std::max(1, *std::max_element(h.counts.begin(), h.counts.end()));
    const double top = y + 14, plot = height - 20, barWidth = w / bins;
    cairo_set_source_rgb(cr, 0.29, 0.48, 0.72);
    for (int b = 0; b < bins; ++b) {
      const double bar = plot * h.counts[b] / most;
      cairo_rectangle(cr, left + b * barWidth, top + plot - bar, barWidth - 1, bar);
    }
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.75, 0.22, 0.17);
    const double meanX = left + w * h.mean / h.top;
    cairo_set_line_width(cr, 1.5);
    cairo_move_to(cr, meanX, top - 6);
    cairo_line_to(cr, meanX, top + plot);
    cairo_stroke(cr);
    font(8);
    char label[96];
    std::snprintf(label, sizeof label, "Ē %.4g %s", h.mean, h.unit.c_str());
    text(meanX + 3, top - 2, label);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 0.5);
    cairo_move_to(cr, left, top + plot);
    cairo_line_to(cr, left + w, top + plot);
    cairo_stroke(cr);
    text(left, top + plot + 10, "0");
    std::snprintf(label, sizeof label, "%.4g %s", h.top, h.unit.c_str());
    text(left + w - width(label), top + plot + 10, label);
    text(kMargin, top + 8, std::to_string(most));
    y += height + 14;
  }
};

cairo_status_t appendBytes(void* closure, const unsigned char* data, unsigned int length) {
  auto* bytes = static_cast<std::vector<std::uint8_t>*>(closure);
  bytes->insert(bytes->end(), data, data + length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

Status writeReportPdf(const LightingReport& report, const std::string& path) {
  std::vector<std::uint8_t> bytes;
  cairo_surface_t* surface = cairo_pdf_surface_create_for_stream(appendBytes, &bytes, kPageWidth, kPageHeight);
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE, report.title.c_str());
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, "lambert");
  cairo_t* cr = cairo_create(surface);
  Sheet sheet{cr, report};
  for (std::size_t p = 0; p < report.pages.size(); ++p) {
    const ReportPage& page = report.pages[p];
    if (p > 0) sheet.newSheet();
    if (p == 0) {
      sheet.font(kTitleSize, true);
      sheet.y += kTitleSize;
      sheet.text(kMargin, sheet.y, report.title);
      sheet.y += 6;
      sheet.paragraph(report.subtitle, 8);
    }
    sheet.font(kHeadingSize + 2, true);
    sheet.y += kHeadingSize + 6;
    sheet.text(kMargin, sheet.y, page.title);
    sheet.y += 6;
    for (const ReportBlock& block : page.blocks) {
      switch (block.kind) {
        case ReportBlock::Kind::Heading:
          sheet.need(kHeadingSize * 5 + 150);  // kept with what follows it: a table's first rows, a histogram
          sheet.font(kHeadingSize, true);
          sheet.y += kHeadingSize * 1.5;
          sheet.text(kMargin, sheet.y, block.text);
          sheet.y += 4;
          break;
        case ReportBlock::Kind::Paragraph: sheet.paragraph(block.text, kBodySize); break;
        case ReportBlock::Kind::Table: sheet.table(block.table); break;
        case ReportBlock::Kind::Image: sheet.image(block.image); break;
        case ReportBlock::Kind::Histogram: sheet.histogram(block.histogram); break;
      }
    }
  }
  sheet.footer();
  cairo_show_page(cr);
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  const cairo_status_t status = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) return Error{path + ": the PDF could not be drawn: " + cairo_status_to_string(status)};
  return writeFileAtomically(path, std::span<const std::uint8_t>(bytes));
}

}  // namespace lambert
