#pragma once
// XML documents (MRML scenes, PLUS device-set configurations) read the way 3D Slicer and PLUS read
// them: VTK's expat-based parser (vtkXMLDataParser, what vtkMRMLParser and PLUS's
// vtkPlusConfig build on), so that what they accept we accept. Its errors become one message that
// names the source and the line, instead of going to VTK's output window.
#include <cstddef>
#include <string>

#include <vtkSmartPointer.h>

class vtkXMLDataElement;

namespace rp {

/// Parses `text`. On failure: nullptr and `error` = "<source>: malformed XML at line N, column M:
/// <expat's reason>" (or why else nothing was read).
vtkSmartPointer<vtkXMLDataElement> ParseXml(const std::string& text, const std::string& source, std::string& error);

/// Reads and parses a file (refusing one over `maxBytes`, default 256 MiB).
vtkSmartPointer<vtkXMLDataElement> ReadXmlFile(const std::string& path, std::string& error,
                                               std::size_t maxBytes = std::size_t(256) << 20);

}  // namespace rp
