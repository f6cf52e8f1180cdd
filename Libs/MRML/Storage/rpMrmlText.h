#pragma once
// The text conventions of 3D Slicer's MRML scene files, as vtkMRMLNode and vtkMRMLStorageNode
// write and read them (one place for each): URL encoding of file names, XML escaping of
// attribute values, the `attributes="key:value;..."` list (with % and ; percent-encoded), the
// `references="role:id id;role:id;"` list, and numbers with enough digits to round-trip.
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace rp {

/// vtkMRMLNode::URLEncodeString: % space ' > < " become %25 %20 %27 %3E %3C %22.
std::string MrmlUrlEncode(const std::string& text);
/// vtkMRMLNode::URLDecodeString (the reverse, in the reverse order).
std::string MrmlUrlDecode(const std::string& text);
/// vtkMRMLNode::XMLAttributeEncodeString: & " ' < > CR LF as XML entities.
std::string MrmlXmlEscape(const std::string& text);

/// The `attributes` value for a node's attributes, and back.
std::string FormatMrmlAttributes(const std::map<std::string, std::string>& attributes);
std::map<std::string, std::string> ParseMrmlAttributes(const std::string& text);

using MrmlReferences = std::vector<std::pair<std::string, std::vector<std::string>>>;  // role -> IDs
/// The `references` value ("role:id1 id2;role2:id3;"), and back (a role seen twice keeps the first).
std::string FormatMrmlReferences(const MrmlReferences& references);
MrmlReferences ParseMrmlReferences(const std::string& text);

/// Numbers separated by spaces, each with 17 significant digits ("1 0 0 0 ..."), and back;
/// ParseNumbers returns false unless exactly `count` finite numbers are read (count 0: any).
std::string FormatNumbers(const double* values, int count);
bool ParseNumbers(const std::string& text, std::vector<double>& values, size_t count = 0);

}  // namespace rp
