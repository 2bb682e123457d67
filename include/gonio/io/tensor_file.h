#pragma once
// Mitsuba's `tensor_file` container, the envelope of the RGL `.bsdf` measured materials
// (Dupuy & Jakob 2018; docs/measured.md). Layout, little-endian throughout (as the RGL
// reference reader rgl-epfl/brdf-loader `powitacq` and Mitsuba's TensorFile read it):
//
//   char[12]  "tensor_file\0"      magic
//   uint8[2]  {1, 0}               version 1.0
//   uint32    n                    number of fields
//   n times:  uint16 name length, name bytes, uint16 rank, uint8 dtype, uint64 offset,
//             uint64 shape[rank]
//   the fields' data at their offsets (row-major, last axis contiguous)
//
// dtype codes: 1 uint8, 2 int8, 3 uint16, 4 int16, 5 uint32, 6 int32, 7 uint64, 8 int64,
// 9 float16, 10 float32, 11 float64 (0 is invalid).
//
// parse_tensor_file refuses every malformed file with one InputError line naming the
// file and the field: a short header, a wrong magic or version, a field table or data
// running past the end, a size that overflows, an unknown dtype, two fields of one name.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gonio {

enum class TensorDtype : std::uint8_t {
  UInt8 = 1, Int8, UInt16, Int16, UInt32, Int32, UInt64, Int64, Float16, Float32, Float64
};

// Bytes per element of `d` (0 for a code that is not a dtype).
std::size_t tensor_dtype_size(TensorDtype d);
std::string_view tensor_dtype_name(TensorDtype d);

struct TensorField {
  std::string name;
  TensorDtype dtype = TensorDtype::Float32;
  std::vector<std::uint64_t> shape;
  std::vector<std::uint8_t> data;  // the raw little-endian bytes
  std::uint64_t count() const;     // product of the shape (1 for rank 0)
};

class TensorFile {
 public:
  // `label` (the file name) starts every error message.
  static TensorFile parse(std::span<const std::uint8_t> bytes, const std::string& label);
  static TensorFile read(const std::string& path);  // InputError if unreadable

  const std::string& label() const { return label_; }
  const std::vector<TensorField>& fields() const { return fields_; }
  const TensorField* find(std::string_view name) const;
  // The field `name`, checked: present, of dtype `d` and rank `rank` (InputError
  // "LABEL: field 'name': ..." otherwise).
  const TensorField& require(std::string_view name, TensorDtype d, std::size_t rank) const;
  // A float32 field of rank `rank` as floats, every value finite (InputError naming the
  // field and the first index that is NaN or infinite).
  std::vector<float> floats(std::string_view name, std::size_t rank) const;
  // "LABEL: field 'name': what" as an InputError.
  [[noreturn]] void fail(std::string_view name, const std::string& what) const;

 private:
  std::string label_;
  std::vector<TensorField> fields_;
};

// The bytes of a tensor file holding `fields` in order, each field's data aligned to 8
// bytes (as Mitsuba's tensor_io.write does). Each field's data must hold count()·size
// bytes (std::invalid_argument otherwise).
std::vector<std::uint8_t> encode_tensor_file(const std::vector<TensorField>& fields);

// A float32 field from values.
TensorField float_field(std::string name, std::vector<std::uint64_t> shape, std::span<const float> values);

}  // namespace gonio
