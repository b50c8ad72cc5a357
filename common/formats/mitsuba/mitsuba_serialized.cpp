// Mitsuba's .serialized mesh files (common/formats/mitsuba/mitsuba_serialized.h): the end-of-file dictionary, one zlib stream per
// shape, every count checked against the data before anything is allocated.
#include "common/formats/mitsuba/mitsuba_serialized.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/formats/assets/gltf_file.h"
#include "common/formats/vertex_welder.h"
#include "common/util/error.h"

namespace firstshot::mitsuba {
namespace {

static_assert(std::endian::native == std::endian::little, "serialized files are little-endian: arrays are copied as they are");

constexpr uint16_t kSerializedFormat = 0x041C;
constexpr uint32_t kSerializedNormals = 0x0001, kSerializedUv = 0x0002, kSerializedColours = 0x0008,
                   kSerializedFaceNormals = 0x0010, kSerializedSingle = 0x1000, kSerializedDouble = 0x2000;
constexpr size_t kSerializedChunk = size_t(1) << 20;  ///< bytes of the file read at a time
constexpr uint64_t kDeflateMaxRatio = 1032;          ///< deflate expands at most this much (zlib's technical notes)
constexpr size_t kMaxShapeName = size_t(1) << 16;     ///< a longer name means a corrupt stream (no NUL)

/// Little-endian unsigned integer of @p n bytes at @p p.
uint64_t littleEndian(const unsigned char* p, int n) {
  uint64_t v = 0;
  for (int i = n - 1; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

/// One shape of one serialized file being read; every error names the scene element, the file and the shape.
class SerializedReader {
 public:
  SerializedReader(const std::string& path, int index, const std::string& sceneFile, const std::string& element)
      : path_(path), index_(index), sceneFile_(sceneFile), element_(element) {}
  ~SerializedReader() {
    if (zlibOpen_) inflateEnd(&z_);
  }
  SerializedReader(const SerializedReader&) = delete;
  SerializedReader& operator=(const SerializedReader&) = delete;

  SerializedShape read();

 private:
  [[noreturn]] void fail(const std::string& what, bool whole = false) const {
    throw InputError(sceneFile_, element_,
                     "serialized file " + path_ + (whole ? "" : ", shape " + std::to_string(index_)) + ": " + what);
  }
  uint64_t readHeader();
  void openStream(uint64_t offset);
  /// Reads the next chunk of the compressed data into the inflater's input; fail(@p truncated) when none is left.
  void refill(const char* truncated);
  void inflateInto(void* dst, size_t n);
  bool streamEnded();
  template <typename T>
  T value() {
    T v;
    inflateInto(&v, sizeof v);
    return v;
  }
  /// @p count reals, as floats or doubles in the file, widened to double.
  std::vector<double> reals(uint64_t count, bool dbl);

  std::string path_;
  int index_;
  std::string sceneFile_, element_;
  std::ifstream in_;
  uint64_t size_ = 0;     ///< the file's size, bytes
  uint16_t version_ = 0;
  uint64_t left_ = 0;     ///< compressed bytes not read yet, up to the end of the file
  z_stream z_{};
  bool zlibOpen_ = false, ended_ = false;
  std::vector<unsigned char> chunk_;
};

/// The offset of shape index_'s header: 0 for the first (read without the dictionary, as Mitsuba does), else from
/// the end-of-file dictionary, checked to lie in the file and to hold a shape header.
uint64_t SerializedReader::readHeader() {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path_, ec)) fail("file not found", true);
  size_ = std::filesystem::file_size(path_, ec);
  in_.open(path_, std::ios::binary);
  if (ec || !in_) fail("cannot open file", true);
  if (isGitLfsPointer(fileHead(path_))) fail(kGitLfsPointerMessage, true);
  unsigned char head[4];
  if (size_ < 4 || !in_.read(reinterpret_cast<char*>(head), 4)) fail("truncated: shorter than its 4-byte header", true);
  if (littleEndian(head, 2) != kSerializedFormat)
    fail("not a Mitsuba serialized file (its first two bytes are not the format identifier 0x041C)", true);
  version_ = uint16_t(littleEndian(head + 2, 2));
  if (version_ != 3 && version_ != 4) fail("format version " + std::to_string(version_) + " is not supported (3 or 4)", true);
  if (index_ == 0) return 0;
  const uint64_t entry = version_ == 4 ? 8 : 4;
  unsigned char tail[8];
  if (size_ < 8) fail("truncated: no end-of-file dictionary to find shape_index " + std::to_string(index_) + " in", true);
  in_.seekg(std::streamoff(size_ - 4));
  in_.read(reinterpret_cast<char*>(tail), 4);
  const uint64_t count = littleEndian(tail, 4);
  if (count == 0 || count > (size_ - 8) / entry)
    fail("corrupt or truncated end-of-file dictionary (it counts " + std::to_string(count) + " shapes in a file of " +
             std::to_string(size_) + " bytes)",
         true);
  if (uint64_t(index_) >= count)
    fail("shape_index " + std::to_string(index_) + " is out of range: the file holds " + std::to_string(count) +
             " shape" + (count == 1 ? "" : "s") + " (0 to " + std::to_string(count - 1) + ")",
         true);
  const uint64_t dictionary = size_ - 4 - count * entry;
  in_.seekg(std::streamoff(dictionary + uint64_t(index_) * entry));
  in_.read(reinterpret_cast<char*>(tail), std::streamsize(entry));
  const uint64_t offset = littleEndian(tail, int(entry));
  unsigned char header[4] = {0, 0, 0, 0};
  if (offset + 4 <= dictionary) {
    in_.seekg(std::streamoff(offset));
    in_.read(reinterpret_cast<char*>(header), 4);
  }
  if (!in_ || littleEndian(header, 2) != kSerializedFormat || littleEndian(header + 2, 2) != version_)
    fail("the end-of-file dictionary gives offset " + std::to_string(offset) +
         ", where no shape header is (corrupt dictionary)");
  return offset;
}

void SerializedReader::openStream(uint64_t offset) {
  in_.clear();
  in_.seekg(std::streamoff(offset + 4));
  left_ = size_ - offset - 4;
  chunk_.resize(size_t(std::min<uint64_t>(left_, kSerializedChunk)) + 1);
  if (inflateInit(&z_) != Z_OK) fail("zlib cannot start decompressing");
  zlibOpen_ = true;
}

void SerializedReader::refill(const char* truncated) {
  if (left_ == 0) fail(truncated);
  const size_t take = size_t(std::min<uint64_t>(left_, chunk_.size()));
  if (!in_.read(reinterpret_cast<char*>(chunk_.data()), std::streamsize(take))) fail("cannot read the file");
  left_ -= take;
  z_.next_in = chunk_.data(), z_.avail_in = uInt(take);
}

void SerializedReader::inflateInto(void* dst, size_t n) {
  z_.next_out = static_cast<Bytef*>(dst);
  size_t done = 0;
  while (done < n) {
    if (ended_) fail("corrupt: the compressed stream ends before the data its header counts");
    if (z_.avail_in == 0) refill("truncated: the file ends inside the shape's compressed data");
    const size_t want = std::min<size_t>(n - done, size_t(1) << 30);
    z_.avail_out = uInt(want);
    const int rc = inflate(&z_, Z_NO_FLUSH);
    done += want - z_.avail_out;
    if (rc == Z_STREAM_END) ended_ = true;
    else if (rc != Z_OK && rc != Z_BUF_ERROR)
      fail(std::string("corrupt compressed data (zlib: ") + (z_.msg ? z_.msg : "error " + std::to_string(rc)) + ")");
  }
}

/// Whether the stream ends right here (its checksum read), as it must once the triangles are read.
bool SerializedReader::streamEnded() {
  unsigned char extra;
  z_.next_out = &extra;
  while (!ended_) {
    if (z_.avail_in == 0) refill("truncated: the file ends before the shape's compressed stream does");
    z_.avail_out = 1;
    const int rc = inflate(&z_, Z_NO_FLUSH);
    if (z_.avail_out == 0) return false;  // one more byte of data
    if (rc == Z_STREAM_END) ended_ = true;
    else if (rc != Z_OK && rc != Z_BUF_ERROR)
      fail(std::string("corrupt compressed data (zlib: ") + (z_.msg ? z_.msg : "error " + std::to_string(rc)) + ")");
  }
  return true;
}

std::vector<double> SerializedReader::reals(uint64_t count, bool dbl) {
  std::vector<double> out(count);
  if (dbl) {
    inflateInto(out.data(), count * sizeof(double));
  } else {
    std::vector<float> f(count);
    inflateInto(f.data(), count * sizeof(float));
    std::copy(f.begin(), f.end(), out.begin());
  }
  return out;
}

SerializedShape SerializedReader::read() {
  const uint64_t offset = readHeader();
  openStream(offset);
  SerializedShape shape;
  const uint32_t flags = value<uint32_t>();
  if ((flags & kSerializedSingle) && (flags & kSerializedDouble))
    fail("corrupt flags: both single and double precision are set");
  const bool dbl = flags & kSerializedDouble;
  if (version_ == 4) {
    for (char c = value<char>(); c != '\0'; c = value<char>()) {
      if (shape.name.size() >= kMaxShapeName) fail("corrupt: the shape's name does not end within 64 KiB");
      shape.name += c;
    }
  }
  const uint64_t vertexCount = value<uint64_t>(), triangleCount = value<uint64_t>();
  const std::string counts = std::to_string(vertexCount) + " vertices, " + std::to_string(triangleCount) + " triangles";
  if (vertexCount == 0 || triangleCount == 0) fail("holds no triangles (" + counts + ")");
  if (vertexCount > UINT32_MAX) fail("more than 2^32 − 1 vertices (" + counts + ")");
  const uint64_t perVertex = 3 + ((flags & kSerializedNormals) ? 3 : 0) + ((flags & kSerializedUv) ? 2 : 0) +
                             ((flags & kSerializedColours) ? 3 : 0);
  const uint64_t vertexBytes = vertexCount * perVertex * (dbl ? 8 : 4);
  const uint64_t room = (left_ + z_.avail_in) * kDeflateMaxRatio + 1024;  // the most the rest of the file inflates to
  if (triangleCount > room / 12 || vertexBytes + triangleCount * 12 > room)
    fail("the counts (" + counts + ") need more data than the rest of the file holds (truncated or corrupt)");
  const std::vector<double> positions = reals(3 * vertexCount, dbl);
  std::vector<double> normals, uv;
  if (flags & kSerializedNormals) normals = reals(3 * vertexCount, dbl);
  if (flags & kSerializedUv) uv = reals(2 * vertexCount, dbl);
  if (flags & kSerializedColours) reals(3 * vertexCount, dbl);  // vertex colours: not used (as in Mitsuba 3)
  std::vector<uint32_t> indices(3 * triangleCount);
  inflateInto(indices.data(), indices.size() * sizeof(uint32_t));
  if (!streamEnded()) fail("corrupt: the data goes on past the " + counts + " its header counts");
  for (uint64_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(positions[i])) fail("vertex " + std::to_string(i / 3) + " is not finite");
  MeshData& m = shape.mesh;
  Welder welder(m.vertices);
  m.faces.resize(triangleCount);
  if (!uv.empty()) m.uv.assign(4 * triangleCount, Vec2(0.0f));
  if (!normals.empty()) m.normals.assign(4 * triangleCount, Vec3(0.0f));
  for (uint64_t t = 0; t < triangleCount; ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint64_t v = indices[3 * t + uint64_t(k)];
      if (v >= vertexCount)
        fail("triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) + " of " + std::to_string(vertexCount));
      m.faces[t].v[k] = welder.index(Vec3d(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]));
      if (!uv.empty()) m.uv[4 * t + uint64_t(k)] = Vec2(float(uv[2 * v]), float(uv[2 * v + 1]));
      if (!normals.empty()) {  // unit, or 0 (the face's own normal) where it is zero or not finite
        const Vec3d n(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
        const double length = glm::length(n);
        m.normals[4 * t + uint64_t(k)] = std::isfinite(length) && length > 0 ? Vec3(n / length) : Vec3(0.0f);
      }
    }
  }
  shape.faceNormals = flags & kSerializedFaceNormals;
  return shape;
}

}  // namespace

SerializedShape readSerializedShape(const std::string& path, int index, const std::string& sceneFile,
                                    const std::string& element) {
  return SerializedReader(path, index, sceneFile, element).read();
}

}  // namespace firstshot::mitsuba
