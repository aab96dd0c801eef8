#include "io/e57_xml.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <vector>

#include <libxml/parser.h>
#include <libxml/tree.h>

namespace pointnpr::e57 {

namespace {

// Deeper nesting than any E57 file has: a guard against a stack overflow.
constexpr int kMaxDepth = 64;

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const size_t e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string element_name(const xmlNode* n) {
  std::string name = reinterpret_cast<const char*>(n->name);
  if (n->ns && n->ns->prefix) name = std::string(reinterpret_cast<const char*>(n->ns->prefix)) + ":" + name;
  return name;
}

void convert(const PagedFile& file, const xmlNode* n, XmlElement& out, int depth) {
  if (depth > kMaxDepth) file.fail("XML nests deeper than " + std::to_string(kMaxDepth) + " elements");
  out.name = element_name(n);
  for (const xmlAttr* a = n->properties; a; a = a->next) {
    xmlChar* v = xmlNodeGetContent(reinterpret_cast<const xmlNode*>(a));
    out.attributes[reinterpret_cast<const char*>(a->name)] = v ? reinterpret_cast<const char*>(v) : "";
    xmlFree(v);
  }
  if (auto it = out.attributes.find("type"); it != out.attributes.end()) out.type = it->second;
  std::string text;
  for (const xmlNode* c = n->children; c; c = c->next) {
    if (c->type == XML_ELEMENT_NODE) {
      out.children.emplace_back();
      convert(file, c, out.children.back(), depth + 1);
    } else if ((c->type == XML_TEXT_NODE || c->type == XML_CDATA_SECTION_NODE) && c->content) {
      text += reinterpret_cast<const char*>(c->content);
    }
  }
  // Strings keep their spaces; numbers are trimmed when parsed.
  out.text = std::move(text);
}

}  // namespace

const XmlElement* XmlElement::child(const std::string& child_name) const {
  for (const XmlElement& c : children)
    if (c.name == child_name) return &c;
  return nullptr;
}

XmlElement parse_xml(const PagedFile& file) {
  const FileHeader& h = file.header();
  if (h.xml_logical_length > static_cast<uint64_t>(std::numeric_limits<int>::max()))
    file.fail("XML section of " + std::to_string(h.xml_logical_length) + " bytes is too large",
              static_cast<int64_t>(h.xml_physical_offset));
  std::vector<uint8_t> xml(static_cast<size_t>(h.xml_logical_length));
  file.copy(file.to_logical(h.xml_physical_offset), xml.size(), xml.data());
  // No network, no entity substitution, no DTD loading: the bytes are data.
  xmlDoc* doc = xmlReadMemory(reinterpret_cast<const char*>(xml.data()), static_cast<int>(xml.size()), "e57.xml",
                              nullptr, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
  if (!doc) {
    const xmlError* err = xmlGetLastError();
    std::string why = err && err->message ? trim(err->message) : "unknown error";
    const int line = err ? err->line : 0;
    xmlResetLastError();
    file.fail("malformed XML section: " + why + (line > 0 ? " (XML line " + std::to_string(line) + ")" : ""),
              static_cast<int64_t>(h.xml_physical_offset));
  }
  XmlElement root;
  try {
    const xmlNode* r = xmlDocGetRootElement(doc);
    if (!r) file.fail("the XML section has no root element", static_cast<int64_t>(h.xml_physical_offset));
    convert(file, r, root, 0);
  } catch (...) {
    xmlFreeDoc(doc);
    throw;
  }
  xmlFreeDoc(doc);
  if (root.name != "e57Root")
    file.fail("the XML root element is <" + root.name + ">, not <e57Root>", static_cast<int64_t>(h.xml_physical_offset));
  return root;
}

double xml_double(const PagedFile& file, const XmlElement* e, double fallback) {
  if (!e) return fallback;
  const std::string t = trim(e->text);
  if (t.empty()) return fallback;
  double v = 0;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
    file.fail("XML element <" + e->name + ">: '" + t + "' is not a finite number");
  return v;
}

int64_t xml_int(const PagedFile& file, const XmlElement* e, int64_t fallback) {
  if (!e) return fallback;
  const std::string t = trim(e->text);
  if (t.empty()) return fallback;
  int64_t v = 0;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || end != t.data() + t.size())
    file.fail("XML element <" + e->name + ">: '" + t + "' is not a 64-bit integer");
  return v;
}

double attr_double(const PagedFile& file, const XmlElement& e, const std::string& attr, double fallback) {
  auto it = e.attributes.find(attr);
  if (it == e.attributes.end()) return fallback;
  const std::string t = trim(it->second);
  double v = 0;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
    file.fail("XML element <" + e.name + ">: " + attr + "='" + t + "' is not a finite number");
  return v;
}

int64_t attr_int(const PagedFile& file, const XmlElement& e, const std::string& attr, int64_t fallback) {
  auto it = e.attributes.find(attr);
  if (it == e.attributes.end()) return fallback;
  const std::string t = trim(it->second);
  int64_t v = 0;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || end != t.data() + t.size())
    file.fail("XML element <" + e.name + ">: " + attr + "='" + t + "' is not a 64-bit integer");
  return v;
}

uint64_t attr_uint(const PagedFile& file, const XmlElement& e, const std::string& attr) {
  auto it = e.attributes.find(attr);
  if (it == e.attributes.end()) file.fail("XML element <" + e.name + "> lacks its " + attr + " attribute");
  const std::string t = trim(it->second);
  uint64_t v = 0;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || end != t.data() + t.size())
    file.fail("XML element <" + e.name + ">: " + attr + "='" + t + "' is not an unsigned 64-bit integer");
  return v;
}

std::string xml_string(const XmlElement* e) { return e ? e->text : std::string(); }

double xml_number(const PagedFile& file, const XmlElement* e, double fallback) {
  if (!e) return fallback;
  if (e->type == "Integer") return static_cast<double>(xml_int(file, e, static_cast<int64_t>(fallback)));
  if (e->type == "ScaledInteger") {
    const double raw = static_cast<double>(xml_int(file, e, 0));
    return raw * attr_double(file, *e, "scale", 1.0) + attr_double(file, *e, "offset", 0.0);
  }
  return xml_double(file, e, fallback);
}

}  // namespace pointnpr::e57
