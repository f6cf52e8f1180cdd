#pragma once
// Label tables: the names and colours of a labelmap's values, as other tools write them.
//   Slicer colour table (.ctbl, .txt):   value name r g b a        (0-255, '#' comments)
//   ITK-SNAP label description (.txt):   IDX R G B A VIS MSH "LABEL" (A in 0..1)
//   a segmentation (.seg.nrrd):          its segments' label values, names, colours and tissue
//                                        classes (the labels' own names, e.g. of an earlier run)
// The text formats are read line by line; a line with a quoted label is ITK-SNAP's, otherwise
// Slicer's.
#include <array>
#include <string>
#include <vector>

namespace rp {

struct LabelEntry {
  long Value = 0;
  std::string Name;
  std::array<double, 3> Color = {1, 1, 1};  // 0..1
  std::string TissueClass;                  // "" when the table does not say (text formats)
};

struct LabelTable {
  std::vector<LabelEntry> Entries;
  const LabelEntry* Find(long value) const;
};

/// Reads any of the formats. Fails naming the file (and line) on a malformed entry, a duplicate
/// value or a file without entries.
bool ReadLabelTable(const std::string& path, LabelTable& table, std::string& error);

/// A colour for a label without a table entry: distinct for neighbouring values, stable.
std::array<double, 3> DefaultLabelColor(long value);

}  // namespace rp
