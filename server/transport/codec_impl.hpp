// Codec<B>'s members, written once: each forwards to the bus's CodecBuffers<B>, which its codec's
// source file defines before including this and instantiating Codec<B> (template class ...).
// Only the bus adapters' codec sources include this.
#pragma once

#include "transport/codec.hpp"

namespace rigid::transport {

template <Bus B>
Codec<B>::Codec() : buffers_(std::make_unique<CodecBuffers<B>>()) {}
template <Bus B>
Codec<B>::~Codec() = default;

template <Bus B>
std::span<const std::uint8_t> Codec<B>::encode(const StateFrame& message) {
  return buffers_->encode(message);
}
template <Bus B>
std::span<const std::uint8_t> Codec<B>::encode(const WrenchCommand& message) {
  return buffers_->encode(message);
}
template <Bus B>
std::span<const std::uint8_t> Codec<B>::encode(const ControlCommand& message) {
  return buffers_->encode(message);
}
template <Bus B>
std::span<const std::uint8_t> Codec<B>::encode(const ControlReply& message) {
  return buffers_->encode(message);
}
template <Bus B>
std::span<const std::uint8_t> Codec<B>::encode(const StatsReport& message) {
  return buffers_->encode(message);
}
template <Bus B>
std::span<const std::uint8_t> Codec<B>::encode(const SceneDescription& message) {
  return buffers_->encode(message);
}
template <Bus B>
std::span<const std::uint8_t> Codec<B>::encode(const AcceptedCommand& message) {
  return buffers_->encode(message);
}

template <Bus B>
std::span<const std::uint8_t> Codec<B>::encode(const ContactEvents& message) {
  return buffers_->encode(message);
}
template <Bus B>
std::span<const std::uint8_t> Codec<B>::encode(const EditCommand& message) {
  return buffers_->encode(message);
}

template <Bus B>
DecodeStatus Codec<B>::decode(std::span<const std::uint8_t> bytes, StateFrame& out) {
  return buffers_->decode(bytes, out);
}
template <Bus B>
DecodeStatus Codec<B>::decode(std::span<const std::uint8_t> bytes, WrenchCommand& out) {
  return buffers_->decode(bytes, out);
}
template <Bus B>
DecodeStatus Codec<B>::decode(std::span<const std::uint8_t> bytes, ControlCommand& out) {
  return buffers_->decode(bytes, out);
}
template <Bus B>
DecodeStatus Codec<B>::decode(std::span<const std::uint8_t> bytes, ControlReply& out) {
  return buffers_->decode(bytes, out);
}
template <Bus B>
DecodeStatus Codec<B>::decode(std::span<const std::uint8_t> bytes, StatsReport& out) {
  return buffers_->decode(bytes, out);
}
template <Bus B>
DecodeStatus Codec<B>::decode(std::span<const std::uint8_t> bytes, SceneDescription& out) {
  return buffers_->decode(bytes, out);
}
template <Bus B>
DecodeStatus Codec<B>::decode(std::span<const std::uint8_t> bytes, AcceptedCommand& out) {
  return buffers_->decode(bytes, out);
}
template <Bus B>
DecodeStatus Codec<B>::decode(std::span<const std::uint8_t> bytes, ContactEvents& out) {
  return buffers_->decode(bytes, out);
}
template <Bus B>
DecodeStatus Codec<B>::decode(std::span<const std::uint8_t> bytes, EditCommand& out) {
  return buffers_->decode(bytes, out);
}

}  // namespace rigid::transport
