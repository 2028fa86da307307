// Where each field of a message parsed from protobuf text format was written, so that validation
// errors found after parsing can still point at a line and column.
#pragma once

#include <google/protobuf/descriptor.h>
#include <google/protobuf/text_format.h>

#include <string_view>

namespace rigid::scene {

// A 1-based position in the text; line 0 means unknown.
struct TextPos {
  int line = 0;
  int column = 0;
};

// A message in the parsed text: its type, where it was written, and the parser's record of where
// its fields were written. Missing fields resolve to the nearest enclosing position that is known,
// so "a field that should have been given" points at the block that lacks it.
class TextNode {
 public:
  using Tree = google::protobuf::TextFormat::ParseInfoTree;

  // The root message; `tree` may be null (no positions known). The root's position is 1:1.
  TextNode(const google::protobuf::Descriptor* type, const Tree* tree);

  const google::protobuf::Descriptor* type() const { return type_; }
  TextPos pos() const { return pos_; }
  // Where `field` (index for repeated fields, -1 otherwise) was written, else pos().
  TextPos at(std::string_view field, int index = -1) const;
  TextPos at(const google::protobuf::FieldDescriptor* field, int index = -1) const;
  // The nested message `field` (must be a message field).
  TextNode child(std::string_view field, int index = -1) const;
  TextNode child(const google::protobuf::FieldDescriptor* field, int index = -1) const;

  // The descriptor of `field`; throws std::logic_error if this message has no such field (a typo
  // in the loader, never the user's fault).
  const google::protobuf::FieldDescriptor* field(std::string_view name) const;

 private:
  TextNode(const google::protobuf::Descriptor* type, const Tree* tree, TextPos pos)
      : type_(type), tree_(tree), pos_(pos) {}

  const google::protobuf::Descriptor* type_;
  const Tree* tree_;
  TextPos pos_;
};

}  // namespace rigid::scene
