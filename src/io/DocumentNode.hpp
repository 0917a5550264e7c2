// A small document tree (null, booleans, numbers, strings, arrays, objects with their keys in insertion order),
// written both as JSON and as YAML: the common form of pkm_verify's reports (ReportDocument.hpp builds it).
// Internal to the io library.
//
// JSON: strict RFC 8259, 2-space indentation, arrays holding no object on one line; numbers by jsonNumber (null for
// inf / NaN), strings by jsonString. YAML: objects in block style, arrays in flow style unless they hold objects
// (then a block sequence), strings double-quoted with JSON escapes (a subset of YAML's double-quoted escapes), keys
// plain when they are identifiers, numbers as in JSON but .inf / -.inf / .nan.
#pragma once

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace pkm_accuracy {
namespace io {

class DocumentNode {
 public:
  enum class Kind { Null, Bool, Number, Integer, String, Array, Object };

  /// null
  DocumentNode() = default;
  static DocumentNode number(double x);
  static DocumentNode integer(long long x);
  static DocumentNode boolean(bool b);
  static DocumentNode string(std::string s);
  /// An empty array / object (push / set add to them).
  static DocumentNode array();
  static DocumentNode object();

  /// Appends an item to an array.
  DocumentNode& push(DocumentNode n);
  /// Appends a member to an object (keys keep their insertion order).
  DocumentNode& set(const std::string& key, DocumentNode n);

  Kind kind() const { return kind_; }

  /// The node as JSON at the given indentation (of the line it starts on); no trailing newline.
  void writeJson(std::ostream& os, int indent) const;
  /// The members of an object as YAML block mappings, one per line, at the given indentation.
  void writeYamlMembers(std::ostream& os, int indent) const;

 private:
  explicit DocumentNode(Kind k) : kind_(k) {}

  /// Holds no object at any depth (arrays of this kind are written on one line).
  bool flat() const;
  bool isNonEmptyObject() const { return kind_ == Kind::Object && !members_.empty(); }
  /// Null, booleans and integers: the same text in JSON and YAML.
  void writeCommonScalar(std::ostream& os) const;
  void writeJsonArray(std::ostream& os, int indent) const;
  void writeJsonObject(std::ostream& os, int indent) const;
  /// A scalar, or an array in flow style (holding no object), or "{}" (an empty object).
  void writeYamlScalarOrFlow(std::ostream& os) const;
  /// The items of an array holding objects, as a YAML block sequence at the given indentation.
  void writeYamlBlockSequence(std::ostream& os, int indent) const;

  Kind kind_ = Kind::Null;
  bool bool_ = false;
  double number_ = 0.0;
  long long integer_ = 0;
  std::string string_;
  std::vector<DocumentNode> items_;
  std::vector<std::pair<std::string, DocumentNode>> members_;
};

}  // namespace io
}  // namespace pkm_accuracy
