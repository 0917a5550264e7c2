#include "DocumentNode.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "pkm_accuracy/io/ResultWriter.hpp"

namespace pkm_accuracy {
namespace io {
namespace {

/// Plain YAML keys for identifiers, double-quoted otherwise.
std::string yamlKey(const std::string& key) {
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
  return plain ? key : jsonString(key);
}

std::string spaces(int n) { return std::string(static_cast<std::size_t>(n), ' '); }

}  // namespace

DocumentNode DocumentNode::number(double x) {
  DocumentNode n(Kind::Number);
  n.number_ = x;
  return n;
}

DocumentNode DocumentNode::integer(long long x) {
  DocumentNode n(Kind::Integer);
  n.integer_ = x;
  return n;
}

DocumentNode DocumentNode::boolean(bool b) {
  DocumentNode n(Kind::Bool);
  n.bool_ = b;
  return n;
}

DocumentNode DocumentNode::string(std::string s) {
  DocumentNode n(Kind::String);
  n.string_ = std::move(s);
  return n;
}

DocumentNode DocumentNode::array() { return DocumentNode(Kind::Array); }

DocumentNode DocumentNode::object() { return DocumentNode(Kind::Object); }

DocumentNode& DocumentNode::push(DocumentNode n) {
  items_.push_back(std::move(n));
  return *this;
}

DocumentNode& DocumentNode::set(const std::string& key, DocumentNode n) {
  members_.emplace_back(key, std::move(n));
  return *this;
}

bool DocumentNode::flat() const {
  if (kind_ == Kind::Object) return false;
  return std::all_of(items_.begin(), items_.end(), [](const DocumentNode& n) { return n.flat(); });
}

void DocumentNode::writeCommonScalar(std::ostream& os) const {
  switch (kind_) {
    case Kind::Bool:
      os << (bool_ ? "true" : "false");
      return;
    case Kind::Integer:
      os << integer_;
      return;
    case Kind::String:
      os << jsonString(string_);
      return;
    default:
      os << "null";
      return;
  }
}

// ---- JSON ----------------------------------------------------------------------------------------------------------
void DocumentNode::writeJson(std::ostream& os, int indent) const {
  switch (kind_) {
    case Kind::Number:
      os << jsonNumber(number_);
      return;
    case Kind::Array:
      writeJsonArray(os, indent);
      return;
    case Kind::Object:
      writeJsonObject(os, indent);
      return;
    default:
      writeCommonScalar(os);
      return;
  }
}

void DocumentNode::writeJsonArray(std::ostream& os, int indent) const {
  if (flat()) {
    os << '[';
    for (std::size_t i = 0; i < items_.size(); ++i) {
      if (i > 0) os << ", ";
      items_[i].writeJson(os, indent);
    }
    os << ']';
    return;
  }
  os << "[\n";
  for (std::size_t i = 0; i < items_.size(); ++i) {
    os << spaces(indent + 2);
    items_[i].writeJson(os, indent + 2);
    os << (i + 1 < items_.size() ? ",\n" : "\n");
  }
  os << spaces(indent) << ']';
}

void DocumentNode::writeJsonObject(std::ostream& os, int indent) const {
  if (members_.empty()) {
    os << "{}";
    return;
  }
  os << "{\n";
  for (std::size_t i = 0; i < members_.size(); ++i) {
    os << spaces(indent + 2) << jsonString(members_[i].first) << ": ";
    members_[i].second.writeJson(os, indent + 2);
    os << (i + 1 < members_.size() ? ",\n" : "\n");
  }
  os << spaces(indent) << '}';
}

// ---- YAML ----------------------------------------------------------------------------------------------------------
void DocumentNode::writeYamlScalarOrFlow(std::ostream& os) const {
  switch (kind_) {
    case Kind::Number:
      if (std::isnan(number_)) {
        os << ".nan";
      } else if (std::isinf(number_)) {
        os << (number_ > 0 ? ".inf" : "-.inf");
      } else {
        os << jsonNumber(number_);
      }
      return;
    case Kind::Array:
      os << '[';
      for (std::size_t i = 0; i < items_.size(); ++i) {
        if (i > 0) os << ", ";
        items_[i].writeYamlScalarOrFlow(os);
      }
      os << ']';
      return;
    case Kind::Object:
      os << "{}";  // only reached for empty objects
      return;
    default:
      writeCommonScalar(os);
      return;
  }
}

void DocumentNode::writeYamlBlockSequence(std::ostream& os, int indent) const {
  for (const DocumentNode& item : items_) {
    os << spaces(indent) << "-";
    if (item.isNonEmptyObject()) {
      os << '\n';
      item.writeYamlMembers(os, indent + 2);
    } else {
      os << ' ';
      item.writeYamlScalarOrFlow(os);
      os << '\n';
    }
  }
}

void DocumentNode::writeYamlMembers(std::ostream& os, int indent) const {
  for (const auto& m : members_) {
    os << spaces(indent) << yamlKey(m.first) << ':';
    if (m.second.isNonEmptyObject()) {
      os << '\n';
      m.second.writeYamlMembers(os, indent + 2);
    } else if (m.second.kind_ == Kind::Array && !m.second.flat()) {
      os << '\n';
      m.second.writeYamlBlockSequence(os, indent + 2);
    } else {
      os << ' ';
      m.second.writeYamlScalarOrFlow(os);
      os << '\n';
    }
  }
}

}  // namespace io
}  // namespace pkm_accuracy
