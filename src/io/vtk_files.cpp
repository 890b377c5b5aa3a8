// VTK XML text (see vtk_files.hpp).
#include "io/vtk_files.hpp"

#include <cstdio>
#include <stdexcept>

namespace millwear::io {

namespace {

// Nine significant digits: finer than any position (nm in a mill) or rate we write.
void put_number(std::string& out, double v, bool integer) {
  char buf[40];
  if (integer) std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(v));
  else std::snprintf(buf, sizeof buf, "%.9g", v);
  out += buf;
}

// A quoted XML attribute value: names are ours, but a design name may hold '&' or quotes.
std::string xml_attr(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

void put_array(std::string& out, const VtkArray& a, std::size_t count) {
  if (a.values.size() != count * static_cast<std::size_t>(a.components))
    throw std::invalid_argument("VTK array " + a.name + ": " + std::to_string(a.values.size()) + " values for " +
                                std::to_string(count) + " items of " + std::to_string(a.components));
  out += "        <DataArray type=\"";
  out += a.integer ? "Int32" : "Float64";
  out += "\" Name=\"" + xml_attr(a.name) + "\" NumberOfComponents=\"" + std::to_string(a.components) +
         "\" format=\"ascii\">\n          ";
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    if (i) out += (i % 12 == 0) ? "\n          " : " ";
    put_number(out, a.values[i], a.integer);
  }
  out += "\n        </DataArray>\n";
}

template <class F>
void put_ints(std::string& out, const char* type, const char* name, std::size_t n, F value) {
  out += std::string("        <DataArray type=\"") + type + "\" Name=\"" + name + "\" format=\"ascii\">\n          ";
  for (std::size_t i = 0; i < n; ++i) {
    if (i) out += (i % 16 == 0) ? "\n          " : " ";
    out += std::to_string(value(i));
  }
  out += "\n        </DataArray>\n";
}

}  // namespace

std::string vtu_text(const VtkGrid& g) {
  const std::size_t np = g.point_count(), nc = g.cell_count();
  if (g.xyz.size() != 3 * np) throw std::invalid_argument("VTK points: not 3 coordinates each");
  std::string out;
  out.reserve(64 * (np + nc) * (1 + g.point_data.size()));
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  out += "  <UnstructuredGrid>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(np) + "\" NumberOfCells=\"" + std::to_string(nc) + "\">\n";
  out += "      <PointData>\n";
  for (const VtkArray& a : g.point_data) put_array(out, a, np);
  out += "      </PointData>\n      <CellData>\n";
  for (const VtkArray& a : g.cell_data) put_array(out, a, nc);
  out += "      </CellData>\n      <Points>\n";
  put_array(out, VtkArray{"Points", 3, false, g.xyz}, np);
  out += "      </Points>\n      <Cells>\n";
  // VTK cell types: 1 = VTK_VERTEX, 3 = VTK_LINE.
  if (g.cells == VtkCells::Vertices) {
    put_ints(out, "Int64", "connectivity", nc, [](std::size_t i) { return static_cast<long long>(i); });
    put_ints(out, "Int64", "offsets", nc, [](std::size_t i) { return static_cast<long long>(i + 1); });
    put_ints(out, "UInt8", "types", nc, [](std::size_t) { return 1; });
  } else {
    put_ints(out, "Int64", "connectivity", 2 * nc, [&](std::size_t i) { return static_cast<long long>(g.line_points[i]); });
    put_ints(out, "Int64", "offsets", nc, [](std::size_t i) { return static_cast<long long>(2 * (i + 1)); });
    put_ints(out, "UInt8", "types", nc, [](std::size_t) { return 3; });
  }
  out += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

std::string pvd_text(const std::vector<PvdEntry>& entries) {
  std::string out = "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const PvdEntry& e : entries) {
    out += "    <DataSet timestep=\"";
    put_number(out, e.time_s, false);
    out += "\" group=\"\" part=\"" + std::to_string(e.part) + "\" file=\"" + xml_attr(e.file) + "\"/>\n";
  }
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

}  // namespace millwear::io
