// Field positions from the text-format parser's ParseInfoTree.
#include "scene/text_location.hpp"

#include <stdexcept>
#include <string>

namespace rigid::scene {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;

TextNode::TextNode(const Descriptor* type, const Tree* tree)
    : TextNode(type, tree, TextPos{1, 1}) {}

const FieldDescriptor* TextNode::field(std::string_view name) const {
  const FieldDescriptor* f = type_->FindFieldByName(std::string(name));
  if (f == nullptr) {
    throw std::logic_error("scene loader: " + type_->full_name() + " has no field '" +
                           std::string(name) + "'");
  }
  return f;
}

TextPos TextNode::at(std::string_view name, int index) const {
  return at(field(name), index);
}

TextPos TextNode::at(const FieldDescriptor* f, int index) const {
  if (tree_ == nullptr) return pos_;
  // The parser records 0-based lines and columns, and -1 for a field it never saw.
  const auto loc = tree_->GetLocation(f, f->is_repeated() ? index : -1);
  if (loc.line < 0) return pos_;
  return TextPos{loc.line + 1, loc.column + 1};
}

TextNode TextNode::child(std::string_view name, int index) const {
  return child(field(name), index);
}

TextNode TextNode::child(const FieldDescriptor* f, int index) const {
  if (f->message_type() == nullptr) {
    throw std::logic_error("scene loader: " + f->full_name() + " is not a message");
  }
  const int i = f->is_repeated() ? index : -1;
  const Tree* nested = tree_ == nullptr ? nullptr : tree_->GetTreeForNested(f, i);
  return TextNode(f->message_type(), nested, at(f, i));
}

}  // namespace rigid::scene
