// The binary files' frame: header, sections, checksum trailer, atomic write, verifying read (binary_file.h).
#include "common/util/binary_file.h"

#include <algorithm>
#include <cerrno>
#include <stdexcept>

#include "common/util/error.h"

namespace firstshot {
namespace {

constexpr size_t kTrailerBytes = 16;      ///< checksum u64, end marker
constexpr size_t kSectionHeadBytes = 12;  ///< tag, length u64 (BinaryWriter::endSection fills in the length)
/// Plain values are gathered into blocks of this size before they are hashed and written (bytes).
constexpr size_t kBlockBytes = size_t(1) << 20;

std::string n(uint64_t v) { return std::to_string(v); }

/// The frame's layout assumes an 8-byte magic and end marker.
const BinaryFormat& checked(const BinaryFormat& f) {
  if (f.magic.size() != 8 || f.endMarker.size() != 8 || f.headerBytes < 12)
    throw std::logic_error("BinaryFormat: the magic and the end marker take 8 bytes, the header at least 12");
  return f;
}

/// "1 byte", "N bytes".
std::string bytesText(uint64_t v) { return n(v) + (v == 1 ? " byte" : " bytes"); }

/// A tag as found in a file, printable whatever its bytes.
std::string printable(const char* p, size_t size) {
  std::string s;
  for (size_t i = 0; i < size; ++i) s += (p[i] >= 0x20 && p[i] < 0x7f) ? p[i] : '?';
  return s;
}

}  // namespace

BinaryWriter::BinaryWriter(std::ostream& out, const BinaryFormat& format)
    : out_(out), endMarker_(checked(format).endMarker) {
  bytes(format.magic.data(), format.magic.size());
  put(format.version);
}

void BinaryWriter::bytes(const void* data, size_t size) {
  const auto* p = static_cast<const char*>(data);
  if (inSection_ || size < kBlockBytes / 16) {
    if (size) {  // resize + copy: GCC 12 warns falsely (-Wstringop-overflow) on vector<char>::insert here
      const size_t at = buf_.size();
      buf_.resize(at + size);
      std::memcpy(buf_.data() + at, p, size);
    }
    if (!inSection_ && buf_.size() >= kBlockBytes) flush();
    return;
  }
  flush();  // a large array outside a section goes to the stream as it is
  hash_.bytes(p, size);
  out_.write(p, std::streamsize(size));
}

void BinaryWriter::beginSection(std::string_view tag) {
  if (inSection_ || tag.size() != 4)
    throw std::logic_error("BinaryWriter: a section inside a section, or a tag not of 4 characters");
  flush();
  inSection_ = true;
  bytes(tag.data(), tag.size());
  const uint64_t placeholder = 0;
  bytes(&placeholder, sizeof placeholder);
}

void BinaryWriter::endSection() {
  if (!inSection_) throw std::logic_error("BinaryWriter: endSection without beginSection");
  const uint64_t length = buf_.size() - kSectionHeadBytes;
  std::memcpy(buf_.data() + 4, &length, sizeof length);
  inSection_ = false;
  flush();
}

void BinaryWriter::finish() {
  if (inSection_) throw std::logic_error("BinaryWriter: finish inside a section");
  flush();
  const uint64_t checksum = hash_.value();
  out_.write(reinterpret_cast<const char*>(&checksum), sizeof checksum);
  out_.write(endMarker_.data(), std::streamsize(endMarker_.size()));
}

void BinaryWriter::flush() {
  hash_.bytes(buf_.data(), buf_.size());
  out_.write(buf_.data(), std::streamsize(buf_.size()));
  buf_.clear();
}

void writeBinaryFile(const std::string& path, const BinaryFormat& format,
                     const std::function<void(BinaryWriter&)>& contents, OnInterrupt onInterrupt) {
  writeAtomically(
      path,
      [&](const std::string& tmp) {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) throw std::runtime_error(path + ": cannot create file");
        BinaryWriter w(f, format);
        contents(w);
        w.finish();
        f.close();
        if (!f) throw std::runtime_error(path + ": write failed (disk full?)");
      },
      onInterrupt);
}

BinaryReader::BinaryReader(const std::string& path, const BinaryFormat& format) : path_(path) {
  checked(format);
  const std::string noun(format.noun), remedy(format.remedy);
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) {
    const int error = errno;  // why the open failed, before anything else can change it
    fail("", "cannot open the " + noun + " (" + std::strerror(error) + "): " + remedy);
  }
  const std::streamoff size = f.tellg();
  if (size < 0) fail("", "cannot read the " + noun);
  data_.resize(static_cast<size_t>(size));  // the whole file in one read
  f.seekg(0);
  if (!f.read(data_.data(), size)) fail("", "cannot read the " + noun);

  const size_t magic = format.magic.size();
  if (data_.size() < magic || std::memcmp(data_.data(), format.magic.data(), magic) != 0)
    fail("header", "not " + std::string(format.identity) + " (wrong magic)");
  if (data_.size() < magic + sizeof(uint32_t))
    fail("header", "truncated " + noun + " (" + bytesText(data_.size()) + ", shorter than its header)");
  uint32_t version;
  std::memcpy(&version, data_.data() + magic, sizeof version);
  if (version != format.version)
    fail("header", "format version " + n(version) + ", this build reads version " + n(format.version) + ": " + remedy);
  const size_t marker = format.endMarker.size();
  if (data_.size() < format.headerBytes + kTrailerBytes ||
      std::memcmp(data_.data() + data_.size() - marker, format.endMarker.data(), marker) != 0)
    fail("trailer", "truncated " + noun + " (end marker missing)");
  pos_ = magic + sizeof version;
  end_ = data_.size() - kTrailerBytes;
  uint64_t stored;
  std::memcpy(&stored, data_.data() + end_, sizeof stored);
  if (binaryChecksum(data_.data(), end_) != stored)
    fail("trailer", "checksum mismatch, the " + noun + " is corrupt: " + remedy);
}

std::string BinaryReader::str(const char* what) {
  const uint32_t size = get<uint32_t>(what);
  if (size > remaining())  // before allocating: a corrupt length must not ask for gigabytes
    fail(what, "truncated or corrupt: a string of " + bytesText(size) + " at offset " + n(pos_) + ", " + n(remaining()) +
                   (inSection_ ? " left in the section" : " left before the trailer"));
  std::string s(size, '\0');
  bytes(s.data(), s.size(), what);
  return s;
}

void BinaryReader::bytes(void* out, size_t size, const char* what) {
  if (size > remaining())
    fail(what, "truncated or corrupt: " + bytesText(size) + " needed at offset " + n(pos_) + ", " + n(remaining()) +
                   (inSection_ ? " left in the section" : " left before the trailer"));
  if (size) std::memcpy(out, data_.data() + pos_, size);
  pos_ += size;
}

void BinaryReader::enter(const char* tag) {
  if (inSection_) throw std::logic_error("BinaryReader: a section inside a section");
  if (remaining() < 4 || std::memcmp(data_.data() + pos_, tag, 4) != 0)
    fail(tag, "section missing or out of order: found \"" +
                  printable(data_.data() + pos_, std::min<uint64_t>(4, remaining())) + "\" at offset " + n(pos_) +
                  " (corrupt file)");
  pos_ += 4;
  const uint64_t length = get<uint64_t>(tag);
  if (length > remaining())
    fail(tag, "section of " + bytesText(length) + " at offset " + n(pos_) + ", only " + bytesText(remaining()) +
                  " left before the trailer (corrupt file)");
  outerEnd_ = end_;
  end_ = pos_ + length;
  inSection_ = true;
}

void BinaryReader::leave(const char* tag) {
  if (!inSection_) throw std::logic_error("BinaryReader: leave without enter");
  if (remaining() != 0)
    fail(tag, "section length does not match its contents: " + bytesText(remaining()) + " not read at offset " +
                  n(pos_) + " (corrupt file)");
  end_ = outerEnd_;
  inSection_ = false;
}

void BinaryReader::expectEnd(const char* what) {
  if (remaining() != 0)
    fail(what, "unexpected bytes after the contents: " + bytesText(remaining()) + " at offset " + n(pos_) +
                   ", before the trailer (corrupt file)");
}

void BinaryReader::fail(const char* what, const std::string& message) const { throw InputError(path_, what, message); }

}  // namespace firstshot
