#pragma once
// VTK XML files for ParaView, written by hand from the documented format ("VTK File Formats",
// XML section): an UnstructuredGrid (.vtu) of points with vertex or line cells and named
// point and cell arrays, ASCII; and a Collection (.pvd) that lists them by time step and part,
// which ParaView opens as one time series. Plain data in, text out; the caller writes it.
#include <cstdint>
#include <string>
#include <vector>

namespace millwear::io {

// One named array: `components` numbers per point (or cell), point after point.
struct VtkArray {
  std::string name;
  int components = 1;
  bool integer = false;          // written as Int32 (ids, species), else Float64
  std::vector<double> values;    // size = components x count
};

enum class VtkCells { Vertices, Lines };  // one vertex per point; or lines given as point pairs

struct VtkGrid {
  std::vector<double> xyz;                // 3 per point
  VtkCells cells = VtkCells::Vertices;
  std::vector<std::int64_t> line_points;  // Lines: 2 per cell (point ids)
  std::vector<VtkArray> point_data, cell_data;
  std::size_t point_count() const { return xyz.size() / 3; }
  std::size_t cell_count() const { return cells == VtkCells::Vertices ? point_count() : line_points.size() / 2; }
};

// The .vtu text of a grid. Throws std::invalid_argument if an array's size does not match.
std::string vtu_text(const VtkGrid& grid);

struct PvdEntry {
  double time_s = 0.0;
  int part = 0;
  std::string file;              // relative to the .pvd
};
std::string pvd_text(const std::vector<PvdEntry>& entries);

}  // namespace millwear::io
