#include "gridshell/exchange/dxf.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <iterator>
#include <set>
#include <string_view>

#include <dl_dxf.h>
#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"

namespace gridshell::exchange {

namespace fs = std::filesystem;

namespace {

/// dxflib's ASCII writer with its format (the group code right-aligned in three columns, a real
/// to 16 decimals without trailing zeros, a handle in upper-case hex) kept in memory: dxflib's
/// own flushes its file after every real, one system call per line (400 000 for the Aquadom
/// frame's two drawings, most of `analyze`'s time). Its file stream is never opened.
class MemoryWriter final : public DL_WriterA {
 public:
  MemoryWriter() : DL_WriterA("", DL_VERSION_2000) {}
  const std::string& text() const { return text_; }

  void dxfReal(int gc, double value) const override {
    std::array<char, 400> buf;  // 16 decimals of the largest double fit
    const auto [end, ec] =
        std::to_chars(buf.data(), buf.data() + buf.size(), value, std::chars_format::fixed, 16);
    std::string_view s(buf.data(), ec == std::errc() ? end - buf.data() : 0);
    const std::size_t dot = s.find('.');
    if (dot != std::string_view::npos)  // "2500.0", "0.25"
      s = s.substr(0, std::max(s.find_last_not_of('0'), dot + 1) + 1);
    put(gc, s);
  }
  void dxfInt(int gc, int value) const override { put(gc, fmt::format("{}", value)); }
  void dxfHex(int gc, int value) const override {
    put(gc, fmt::format("{:X}", static_cast<unsigned>(value)));
  }
  void dxfString(int gc, const char* value) const override { put(gc, value); }
  void dxfString(int gc, const std::string& value) const override { put(gc, value); }

 private:
  void put(int gc, std::string_view value) const {
    fmt::format_to(std::back_inserter(text_), "{:>3}\n{}\n", gc, value);
  }
  mutable std::string text_;
};

void check(const fs::path& path, const DxfDrawing& d) {
  std::set<std::string> layers;
  for (const DxfLayer& l : d.layers) layers.insert(l.name);
  const auto known = [&](const std::string& layer) {
    if (!layers.count(layer)) throw Error(path.string(), "internal: unlisted DXF layer " + layer);
  };
  const auto finite = [&](const Eigen::Vector2d& p) {
    if (!p.allFinite()) throw Error(path.string(), "internal: refusing to write a non-finite number");
  };
  for (const DxfPolyline& p : d.polylines) {
    known(p.layer);
    for (const auto& x : p.points) finite(x);
  }
  for (const DxfText& t : d.texts) {
    known(t.layer);
    finite(t.at);
    if (!(t.height > 0) || !std::isfinite(t.height))
      throw Error(path.string(), "internal: a text height must be > 0");
  }
}

/// The tables every AutoCAD 2000 reader expects before the entities (dxflib's sequence).
void write_tables(DL_Dxf& dxf, DL_WriterA& w, const DxfDrawing& d) {
  w.sectionTables();
  dxf.writeVPort(w);
  w.tableLinetypes(3);
  dxf.writeLinetype(w, DL_LinetypeData("BYBLOCK", "BYBLOCK", 0, 0, 0.0));
  dxf.writeLinetype(w, DL_LinetypeData("BYLAYER", "BYLAYER", 0, 0, 0.0));
  dxf.writeLinetype(w, DL_LinetypeData("CONTINUOUS", "Continuous", 0, 0, 0.0));
  w.tableEnd();
  w.tableLayers(static_cast<int>(d.layers.size()) + 1);
  dxf.writeLayer(w, DL_LayerData("0", 0), DL_Attributes("", 7, 0, "CONTINUOUS", 1.0));
  for (const DxfLayer& l : d.layers)
    dxf.writeLayer(w, DL_LayerData(l.name, 0), DL_Attributes("", l.colour, 0, "CONTINUOUS", 1.0));
  w.tableEnd();
  w.tableStyle(1);
  dxf.writeStyle(w, DL_StyleData("Standard", 0, 0.0, 1.0, 0.0, 0, 2.5, "txt", ""));
  w.tableEnd();
  dxf.writeView(w);
  dxf.writeUcs(w);
  w.tableAppid(1);
  dxf.writeAppid(w, "ACAD");
  w.tableEnd();
  dxf.writeDimStyle(w, 1, 1, 1, 1, 1);
  dxf.writeBlockRecord(w);
  w.tableEnd();
  w.sectionEnd();
  w.sectionBlocks();
  for (const char* block : {"*Model_Space", "*Paper_Space", "*Paper_Space0"}) {
    dxf.writeBlock(w, DL_BlockData(block, 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(w, block);
  }
  w.sectionEnd();
}

void write_entities(DL_Dxf& dxf, DL_WriterA& w, const DxfDrawing& d) {
  w.sectionEntities();
  for (const DxfPolyline& p : d.polylines) {
    const DL_Attributes attributes(p.layer, 256, 0, "BYLAYER", 1.0);  // colour 256: by layer
    dxf.writePolyline(w,
                      DL_PolylineData(static_cast<int>(p.points.size()), 0, 0, p.closed ? 1 : 0),
                      attributes);
    for (const auto& x : p.points) dxf.writeVertex(w, DL_VertexData(x.x(), x.y(), 0.0, 0.0));
    dxf.writePolylineEnd(w);
  }
  for (const DxfText& t : d.texts) {
    // Justification: horizontal 4 ("middle", centred both ways) at the alignment point.
    const DL_TextData text(t.at.x(), t.at.y(), 0.0, t.at.x(), t.at.y(), 0.0, t.height, 1.0, 0, 4,
                           0, t.text, "Standard", 0.0);
    dxf.writeText(w, text, DL_Attributes(t.layer, 256, 0, "BYLAYER", 1.0));
  }
  w.sectionEnd();
}

}  // namespace

void write_dxf(const fs::path& path, const DxfDrawing& drawing) {
  check(path, drawing);
  DL_Dxf dxf;  // AutoCAD 2000 (AC1015), dxflib's default
  MemoryWriter w;
  dxf.writeHeader(w);
  w.dxfString(9, "$INSUNITS");
  w.dxfInt(70, drawing.units == DxfUnits::millimetres ? 4 : 6);
  w.dxfString(9, "$MEASUREMENT");
  w.dxfInt(70, 1);  // metric
  w.sectionEnd();
  write_tables(dxf, w, drawing);
  write_entities(dxf, w, drawing);
  dxf.writeObjects(w);
  dxf.writeObjectsEnd(w);
  w.dxfEOF();
  io::write_file_atomic(path, w.text());
}

}  // namespace gridshell::exchange
