#pragma once
// The XML section of an E57 file as a small tree of elements (libxml2 parses
// it; nothing of libxml2 leaks out of e57_xml.cpp), with typed accessors that
// throw ReadError for values that are not what the standard says.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "io/e57_pages.h"

namespace pointnpr::e57 {

struct XmlElement {
  std::string name;  // with its namespace prefix ("nor:normalX"), as in the file
  std::string type;  // the E57 "type" attribute: Structure, Vector, Float, ...
  std::map<std::string, std::string> attributes;
  std::string text;  // trimmed text content of a leaf (Integer, Float, String)
  std::vector<XmlElement> children;

  const XmlElement* child(const std::string& child_name) const;
};

// Parses the XML section; `file` names the errors.
XmlElement parse_xml(const PagedFile& file);

// Typed reads of an element's value or attribute; `fallback` when absent.
// A value that does not parse throws ReadError through `file`.
double xml_double(const PagedFile& file, const XmlElement* e, double fallback);
int64_t xml_int(const PagedFile& file, const XmlElement* e, int64_t fallback);
double attr_double(const PagedFile& file, const XmlElement& e, const std::string& attr, double fallback);
int64_t attr_int(const PagedFile& file, const XmlElement& e, const std::string& attr, int64_t fallback);
uint64_t attr_uint(const PagedFile& file, const XmlElement& e, const std::string& attr);
std::string xml_string(const XmlElement* e);
// The value of a numeric element whatever its E57 type: Float, Integer, or
// ScaledInteger (stored integer * scale + offset).
double xml_number(const PagedFile& file, const XmlElement* e, double fallback);

}  // namespace pointnpr::e57
