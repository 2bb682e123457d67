// Mitsuba's tensor_file container (include/gonio/io/tensor_file.h): parse and encode.

#include "gonio/io/tensor_file.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>

#include "gonio/error.h"

namespace gonio {

namespace {

constexpr char kTensorMagic[12] = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', '\0'};
// The largest file read: the RGL database's largest files are about 90 MB.
constexpr std::uint64_t kTensorMaxBytes = std::uint64_t(1) << 31;

// Reads little-endian integers from a byte span, failing with the field's name.
struct TensorCursor {
  std::span<const std::uint8_t> bytes;
  std::size_t pos = 0;
  const std::string& label;

  template <typename T>
  T get(const std::string& what) {
    if (bytes.size() - pos < sizeof(T))
      throw InputError(label + ": truncated: " + what + " at byte " + std::to_string(pos) + " runs past the end (" +
                       std::to_string(bytes.size()) + " bytes)");
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) v |= std::uint64_t(bytes[pos + i]) << (8 * i);
    pos += sizeof(T);
    return static_cast<T>(v);
  }
};

}  // namespace

std::size_t tensor_dtype_size(TensorDtype d) {
  switch (d) {
    case TensorDtype::UInt8: case TensorDtype::Int8: return 1;
    case TensorDtype::UInt16: case TensorDtype::Int16: case TensorDtype::Float16: return 2;
    case TensorDtype::UInt32: case TensorDtype::Int32: case TensorDtype::Float32: return 4;
    case TensorDtype::UInt64: case TensorDtype::Int64: case TensorDtype::Float64: return 8;
  }
  return 0;
}

std::string_view tensor_dtype_name(TensorDtype d) {
  switch (d) {
    case TensorDtype::UInt8: return "uint8";
    case TensorDtype::Int8: return "int8";
    case TensorDtype::UInt16: return "uint16";
    case TensorDtype::Int16: return "int16";
    case TensorDtype::UInt32: return "uint32";
    case TensorDtype::Int32: return "int32";
    case TensorDtype::UInt64: return "uint64";
    case TensorDtype::Int64: return "int64";
    case TensorDtype::Float16: return "float16";
    case TensorDtype::Float32: return "float32";
    case TensorDtype::Float64: return "float64";
  }
  return "invalid";
}

std::uint64_t TensorField::count() const {
  std::uint64_t n = 1;
  for (const std::uint64_t s : shape) n *= s;
  return n;
}

TensorFile TensorFile::parse(std::span<const std::uint8_t> bytes, const std::string& label) {
  TensorFile tf;
  tf.label_ = label;
  if (bytes.size() > kTensorMaxBytes)
    throw InputError(label + ": oversized: " + std::to_string(bytes.size()) + " bytes (at most " +
                     std::to_string(kTensorMaxBytes) + ")");
  if (bytes.size() < 18)
    throw InputError(label + ": truncated: " + std::to_string(bytes.size()) +
                     " bytes, shorter than the 18-byte tensor_file header");
  if (std::memcmp(bytes.data(), kTensorMagic, sizeof kTensorMagic) != 0)
    throw InputError(label + ": not a tensor_file (the first 12 bytes are not \"tensor_file\\0\")");
  if (bytes[12] != 1 || bytes[13] != 0)
    throw InputError(label + ": tensor_file version " + std::to_string(bytes[12]) + "." + std::to_string(bytes[13]) +
                     ", only 1.0 is read");
  TensorCursor c{bytes, 14, label};
  const std::uint32_t n = c.get<std::uint32_t>("the field count");
  // Each field's header takes at least 13 bytes: a count beyond that is a lie.
  if (n > (bytes.size() - c.pos) / 13)
    throw InputError(label + ": truncated: " + std::to_string(n) + " fields announced, the file has room for at most " +
                     std::to_string((bytes.size() - c.pos) / 13));
  tf.fields_.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::string idx = "field #" + std::to_string(i);
    const std::uint16_t name_len = c.get<std::uint16_t>(idx + "'s name length");
    if (bytes.size() - c.pos < name_len)
      throw InputError(label + ": truncated: " + idx + "'s name runs past the end");
    TensorField f;
    f.name.assign(reinterpret_cast<const char*>(bytes.data() + c.pos), name_len);
    c.pos += name_len;
    const std::string what = "field '" + f.name + "'";
    if (tf.find(f.name)) throw InputError(label + ": " + what + " appears twice");
    const std::uint16_t rank = c.get<std::uint16_t>(what + "'s rank");
    const std::uint8_t dtype = c.get<std::uint8_t>(what + "'s dtype");
    const std::uint64_t offset = c.get<std::uint64_t>(what + "'s offset");
    if (dtype == 0 || dtype > std::uint8_t(TensorDtype::Float64))
      throw InputError(label + ": " + what + ": unknown dtype code " + std::to_string(dtype));
    f.dtype = TensorDtype(dtype);
    const std::size_t elem = tensor_dtype_size(f.dtype);
    std::uint64_t total = elem;
    for (std::uint16_t k = 0; k < rank; ++k) {
      const std::uint64_t s = c.get<std::uint64_t>(what + "'s shape");
      f.shape.push_back(s);
      if (s != 0 && total > kTensorMaxBytes / s)
        throw InputError(label + ": " + what + ": oversized: shape gives more than " + std::to_string(kTensorMaxBytes) +
                         " bytes");
      total *= s;
    }
    if (offset > bytes.size() || total > bytes.size() - offset)
      throw InputError(label + ": " + what + ": truncated: " + std::to_string(total) + " bytes at offset " +
                       std::to_string(offset) + " run past the end (" + std::to_string(bytes.size()) + " bytes)");
    f.data.assign(bytes.begin() + std::ptrdiff_t(offset), bytes.begin() + std::ptrdiff_t(offset + total));
    tf.fields_.push_back(std::move(f));
  }
  return tf;
}

TensorFile TensorFile::read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(path + ": cannot read the file");
  if (std::uint64_t(size) > kTensorMaxBytes)
    throw InputError(path + ": oversized: " + std::to_string(size) + " bytes (at most " +
                     std::to_string(kTensorMaxBytes) + ")");
  in.seekg(0);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
    throw InputError(path + ": cannot read the file");
  return parse(bytes, path);
}

const TensorField* TensorFile::find(std::string_view name) const {
  for (const TensorField& f : fields_)
    if (f.name == name) return &f;
  return nullptr;
}

void TensorFile::fail(std::string_view name, const std::string& what) const {
  throw InputError(label_ + ": field '" + std::string(name) + "': " + what);
}

const TensorField& TensorFile::require(std::string_view name, TensorDtype d, std::size_t rank) const {
  const TensorField* f = find(name);
  if (!f) throw InputError(label_ + ": field '" + std::string(name) + "' is missing");
  if (f->dtype != d)
    fail(name, "dtype " + std::string(tensor_dtype_name(f->dtype)) + ", expected " + std::string(tensor_dtype_name(d)));
  if (f->shape.size() != rank)
    fail(name, "rank " + std::to_string(f->shape.size()) + ", expected " + std::to_string(rank));
  return *f;
}

std::vector<float> TensorFile::floats(std::string_view name, std::size_t rank) const {
  const TensorField& f = require(name, TensorDtype::Float32, rank);
  std::vector<float> v(f.data.size() / 4);
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::uint32_t u = 0;
    for (int b = 0; b < 4; ++b) u |= std::uint32_t(f.data[4 * i + std::size_t(b)]) << (8 * b);
    v[i] = std::bit_cast<float>(u);
    if (!std::isfinite(v[i])) fail(name, "value " + format_number(v[i]) + " at index " + std::to_string(i));
  }
  return v;
}

std::vector<std::uint8_t> encode_tensor_file(const std::vector<TensorField>& fields) {
  std::vector<std::uint8_t> out(kTensorMagic, kTensorMagic + sizeof kTensorMagic);
  auto put = [&out](std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out.push_back(std::uint8_t(v >> (8 * i)));
  };
  out.push_back(1);
  out.push_back(0);
  put(fields.size(), 4);
  std::uint64_t offset = 18;
  for (const TensorField& f : fields) offset += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
  std::vector<std::uint64_t> offsets;
  for (const TensorField& f : fields) {
    if (f.data.size() != f.count() * tensor_dtype_size(f.dtype))
      throw std::invalid_argument("encode_tensor_file: field '" + f.name + "' holds the wrong number of bytes");
    offset = (offset + 7) / 8 * 8;
    offsets.push_back(offset);
    offset += f.data.size();
  }
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const TensorField& f = fields[i];
    put(f.name.size(), 2);
    out.insert(out.end(), f.name.begin(), f.name.end());
    put(f.shape.size(), 2);
    put(std::uint64_t(f.dtype), 1);
    put(offsets[i], 8);
    for (const std::uint64_t s : f.shape) put(s, 8);
  }
  for (std::size_t i = 0; i < fields.size(); ++i) {
    out.resize(offsets[i], 0);
    out.insert(out.end(), fields[i].data.begin(), fields[i].data.end());
  }
  return out;
}

TensorField float_field(std::string name, std::vector<std::uint64_t> shape, std::span<const float> values) {
  TensorField f;
  f.name = std::move(name);
  f.dtype = TensorDtype::Float32;
  f.shape = std::move(shape);
  f.data.resize(values.size() * 4);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::uint32_t u = std::bit_cast<std::uint32_t>(values[i]);
    for (int b = 0; b < 4; ++b) f.data[4 * i + std::size_t(b)] = std::uint8_t(u >> (8 * b));
  }
  return f;
}

}  // namespace gonio
