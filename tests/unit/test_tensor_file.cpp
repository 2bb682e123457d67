// Mitsuba's tensor_file container (include/gonio/io/tensor_file.h, issue 59): files built
// byte by byte here from the layout the RGL reference reader (rgl-epfl/brdf-loader,
// powitacq) reads, independent of gonio's encoder; every malformed file is refused in one
// line that names the field.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "gonio/error.h"
#include "gonio/io/tensor_file.h"

namespace gonio {
namespace {

using Bytes = std::vector<std::uint8_t>;

void tf_put(Bytes& b, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) b.push_back(std::uint8_t((v >> (8 * i)) & 0xff));
}
void tf_put_float(Bytes& b, float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  tf_put(b, u, 4);
}

// A file of two fields: "theta_i" float32 [3] = {0, 0.5, 1} and "jacobian" uint8 [1] = {1}.
// Header: 12 + 2 + 4 = 18; field 1: 2 + 7 + 2 + 1 + 8 + 8 = 28; field 2: 2 + 8 + 2 + 1 + 8
// + 8 = 29; data of field 1 at 75 (12 bytes), field 2 at 87.
Bytes tf_two_fields() {
  Bytes b = {'t', 'e', 'n', 's', 'o', 'r', '_', 'f', 'i', 'l', 'e', 0, 1, 0};
  tf_put(b, 2, 4);
  tf_put(b, 7, 2);
  for (char c : std::string("theta_i")) b.push_back(std::uint8_t(c));
  tf_put(b, 1, 2);
  b.push_back(10);  // float32
  tf_put(b, 75, 8);
  tf_put(b, 3, 8);
  tf_put(b, 8, 2);
  for (char c : std::string("jacobian")) b.push_back(std::uint8_t(c));
  tf_put(b, 1, 2);
  b.push_back(1);  // uint8
  tf_put(b, 87, 8);
  tf_put(b, 1, 8);
  EXPECT_EQ(b.size(), 75u);
  tf_put_float(b, 0.f);
  tf_put_float(b, 0.5f);
  tf_put_float(b, 1.f);
  b.push_back(1);
  return b;
}

std::string tf_error(const Bytes& b) {
  try {
    (void)TensorFile::parse(b, "x.bsdf");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TensorFile, ReadsFieldsBuiltByteByByte) {
  const TensorFile tf = TensorFile::parse(tf_two_fields(), "x.bsdf");
  ASSERT_EQ(tf.fields().size(), 2u);
  const std::vector<float> t = tf.floats("theta_i", 1);
  EXPECT_EQ(t, (std::vector<float>{0.f, 0.5f, 1.f}));
  const TensorField& j = tf.require("jacobian", TensorDtype::UInt8, 1);
  ASSERT_EQ(j.data.size(), 1u);
  EXPECT_EQ(j.data[0], 1);
  EXPECT_EQ(j.shape, (std::vector<std::uint64_t>{1}));
}

TEST(TensorFile, EncoderWritesWhatTheParserReads) {
  // The encoder's bytes decode to the same fields, with 8-byte aligned data.
  const std::vector<float> v = {1.f, -2.f, 3.5f, 4.f, 5.f, 6.f};
  TensorField u;
  u.name = "description";
  u.dtype = TensorDtype::UInt8;
  u.shape = {3};
  u.data = {'a', 'b', 'c'};
  const Bytes b = encode_tensor_file({u, float_field("ndf", {2, 3}, v)});
  const TensorFile tf = TensorFile::parse(b, "y");
  EXPECT_EQ(tf.floats("ndf", 2), v);
  EXPECT_EQ(tf.require("description", TensorDtype::UInt8, 1).data, u.data);
  // The first field's data offset (bytes 18 + 2 + 11 + 2 + 1 = 34..41) is 8-aligned.
  std::uint64_t off = 0;
  for (int i = 0; i < 8; ++i) off |= std::uint64_t(b[34 + std::size_t(i)]) << (8 * i);
  EXPECT_EQ(off % 8, 0u);
  EXPECT_EQ(b[off], 'a');
}

TEST(TensorFile, RefusesEachMalformedFileInOneLineNamingTheField) {
  const Bytes good = tf_two_fields();
  auto expect = [](const Bytes& b, const std::string& part) {
    const std::string e = tf_error(b);
    EXPECT_NE(e.find(part), std::string::npos) << "message: " << e << "\nexpected: " << part;
    EXPECT_EQ(e.find('\n'), std::string::npos);
    EXPECT_EQ(e.rfind("x.bsdf", 0), 0u) << e;
  };
  expect(Bytes(good.begin(), good.begin() + 10), "truncated");
  Bytes magic = good;
  magic[0] = 'T';
  expect(magic, "not a tensor_file");
  Bytes version = good;
  version[12] = 2;
  expect(version, "version 2.0");
  // Truncated data: the last byte (jacobian's) is cut.
  expect(Bytes(good.begin(), good.end() - 1), "field 'jacobian': truncated");
  // Truncated before the first field's data (its header whole, the second's cut).
  expect(Bytes(good.begin(), good.begin() + 60), "field 'theta_i': truncated");
  // An unknown dtype code.
  Bytes dtype = good;
  dtype[18 + 2 + 7 + 2] = 12;
  expect(dtype, "field 'theta_i': unknown dtype code 12");
  // A shape whose byte count overflows 64 bits.
  Bytes big = good;
  for (int i = 0; i < 8; ++i) big[18 + 2 + 7 + 2 + 1 + 8 + std::size_t(i)] = 0xff;
  expect(big, "field 'theta_i': oversized");
  // An offset past the end.
  Bytes off = good;
  off[18 + 2 + 7 + 2 + 1] = 200;
  expect(off, "field 'theta_i': truncated");
  // A field count the file cannot hold.
  Bytes count = good;
  count[17] = 0x7f;
  expect(count, "fields announced");
  // A NaN value, a wrong dtype, a wrong rank, a missing field: named by the accessors.
  Bytes nan = good;
  const float q = std::numeric_limits<float>::quiet_NaN();
  std::uint32_t u;
  std::memcpy(&u, &q, 4);
  for (int i = 0; i < 4; ++i) nan[79 + std::size_t(i)] = std::uint8_t(u >> (8 * i));
  const TensorFile tn = TensorFile::parse(nan, "x.bsdf");
  auto accessor_error = [](auto&& call) -> std::string {
    try {
      call();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(accessor_error([&] { (void)tn.floats("theta_i", 1); }), "x.bsdf: field 'theta_i': value nan at index 1");
  EXPECT_EQ(accessor_error([&] { (void)tn.floats("jacobian", 1); }),
            "x.bsdf: field 'jacobian': dtype uint8, expected float32");
  EXPECT_EQ(accessor_error([&] { (void)tn.floats("theta_i", 2); }), "x.bsdf: field 'theta_i': rank 1, expected 2");
  EXPECT_EQ(accessor_error([&] { (void)tn.floats("ndf", 2); }), "x.bsdf: field 'ndf' is missing");
  // Two fields of one name.
  Bytes twice = good;
  const char* name = "theta_i";
  for (int i = 0; i < 7; ++i) twice[18 + 28 + 2 + std::size_t(i)] = std::uint8_t(name[i]);
  twice[18 + 28 + 2 + 7] = 0;  // "theta_i\0" is 8 bytes, a different name: make it equal
  twice[18 + 28] = 7;
  // With the name length 7 the rest of the header is misread; the duplicate is found
  // before that.
  expect(twice, "field 'theta_i' appears twice");
}

}  // namespace
}  // namespace gonio
