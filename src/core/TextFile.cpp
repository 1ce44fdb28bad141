#include "conftrack/core/TextFile.hpp"

#include "conftrack/core/Error.hpp"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <system_error>
#include <unistd.h>

namespace conftrack {

namespace {

/// zlib counts bytes in 32-bit uInt; larger buffers are fed in slices.
constexpr std::size_t kMaxZlibChunk = std::size_t{1} << 30;

/// Hands zlib the next chunk of `in` once it has used up the last one
/// (zlib counts input in 32-bit uInt); `consumed` is what it got so far.
void feedZlib(z_stream& zs, std::string_view in, std::size_t& consumed) {
  if (zs.avail_in == 0 && consumed < in.size()) {
    const std::size_t n = std::min(in.size() - consumed, kMaxZlibChunk);
    // zlib's interface is not const-correct; it does not write the input.
    zs.next_in =
        reinterpret_cast<Bytef*>(const_cast<char*>(in.data())) + consumed;
    zs.avail_in = static_cast<uInt>(n);
    consumed += n;
  }
}

bool isGzipMagic(std::string_view data, std::size_t pos) {
  return data.size() >= pos + 2 &&
         static_cast<unsigned char>(data[pos]) == 0x1f &&
         static_cast<unsigned char>(data[pos + 1]) == 0x8b;
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

std::string tooLarge(std::size_t maxBytes) {
  return "larger than " + std::to_string(maxBytes) +
         " bytes (the limit of conftrack's text files)";
}

std::string readRaw(const std::filesystem::path& file, std::size_t maxBytes) {
  std::string name = file.string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    throw InputError(location(name), "is a directory, expected a file");
  }
  FilePtr f(std::fopen(name.c_str(), "rb"));
  if (!f) {
    const int error = errno;
    std::string what = std::string("cannot open: ") + std::strerror(error);
    if (error == ENOENT) {
      throw MissingFileError(location(name), what);
    }
    throw InputError(location(name), what);
  }
  std::string data;
  // The size is only a hint (the file may change underneath, and devices
  // such as /dev/zero report none): read to EOF, at most maxBytes + 1.
  auto size = std::filesystem::file_size(file, ec);
  if (!ec && size > maxBytes) {
    throw InputError(location(name), tooLarge(maxBytes));
  }
  data.resize(ec ? std::min(std::size_t{1} << 16, maxBytes + 1)
                 : static_cast<std::size_t>(size) + 1);
  std::size_t used = 0;
  for (;;) {
    if (used == data.size()) {
      if (used > maxBytes) {
        throw InputError(location(name), tooLarge(maxBytes));
      }
      data.resize(std::min(data.size() * 2, maxBytes + 1));
    }
    std::size_t n =
        std::fread(data.data() + used, 1, data.size() - used, f.get());
    used += n;
    if (n == 0) {
      if (std::ferror(f.get())) {
        throw InputError(location(name),
                         std::string("read error: ") + std::strerror(errno));
      }
      break;
    }
  }
  if (used > maxBytes) {
    throw InputError(location(name), tooLarge(maxBytes));
  }
  data.resize(used);
  return data;
}

/// Decompresses all gzip members of `in`.
std::string gunzip(std::string_view in, const std::string& name,
                   std::size_t maxBytes) {
  z_stream zs{};
  if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) {
    throw std::runtime_error("zlib: inflateInit2 failed");
  }
  struct Guard {
    z_stream* s;
    ~Guard() { inflateEnd(s); }
  } guard{&zs};

  // The gzip trailer holds the uncompressed size modulo 2^32 of the last
  // member: a good first guess that avoids regrowing the output.
  std::size_t guess = in.size() * 4;
  if (in.size() >= 18) {
    const auto* t =
        reinterpret_cast<const unsigned char*>(in.data() + in.size() - 4);
    std::size_t isize = t[0] | (t[1] << 8) | (t[2] << 16) |
                        (static_cast<std::size_t>(t[3]) << 24);
    // Deflate compresses at most ~1032:1; a corrupt trailer must not make
    // us allocate gigabytes up front.
    guess = std::max(guess / 2, std::min(isize, in.size() * 1032));
  }
  guess = std::min(guess, maxBytes);
  std::string out(guess + 1, '\0');
  std::size_t produced = 0;
  std::size_t consumed = 0;  // bytes of `in` handed to zlib so far
  zs.avail_in = 0;
  for (;;) {
    feedZlib(zs, in, consumed);
    if (produced == out.size()) {
      // One byte beyond the limit tells that the data exceed it.
      if (produced > maxBytes) {
        throw InputError(location(name),
                         "decompressed data " + tooLarge(maxBytes));
      }
      out.resize(std::min(out.size() * 2, maxBytes + 1));
    }
    std::size_t room = std::min(out.size() - produced, kMaxZlibChunk);
    zs.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
    zs.avail_out = static_cast<uInt>(room);
    int rc = inflate(&zs, Z_NO_FLUSH);
    produced += room - zs.avail_out;
    std::size_t position = consumed - zs.avail_in;  // next unread input byte
    if (rc == Z_STREAM_END) {
      if (position == in.size()) {
        break;
      }
      // Concatenated members are legal gzip; anything else is not ours.
      if (!isGzipMagic(in, position)) {
        throw InputError(location(name),
                         "trailing garbage after the gzip data at byte " +
                             std::to_string(position));
      }
      inflateReset(&zs);
      continue;
    }
    if (rc == Z_OK) {
      continue;
    }
    // There is always output room, so Z_BUF_ERROR means zlib needs input
    // that is not there.
    if (rc == Z_BUF_ERROR && position == in.size()) {
      throw InputError(location(name),
                       "unexpected end of file: truncated gzip data");
    }
    throw InputError(location(name),
                     std::string("corrupt gzip data: ") +
                         (zs.msg != nullptr ? zs.msg : zError(rc)));
  }
  if (produced > maxBytes) {
    throw InputError(location(name), "decompressed data " + tooLarge(maxBytes));
  }
  out.resize(produced);
  return out;
}

std::string gzip(std::string_view in, int level) {
  z_stream zs{};
  if (deflateInit2(&zs, std::clamp(level, 1, 9), Z_DEFLATED, 16 + MAX_WBITS, 8,
                   Z_DEFAULT_STRATEGY) != Z_OK) {
    throw std::runtime_error("zlib: deflateInit2 failed");
  }
  struct Guard {
    z_stream* s;
    ~Guard() { deflateEnd(s); }
  } guard{&zs};
  std::string out;
  out.resize(std::max<std::size_t>(
      deflateBound(&zs, static_cast<uLong>(std::min(in.size(), kMaxZlibChunk))),
      1024));
  std::size_t produced = 0;
  std::size_t consumed = 0;
  for (;;) {
    feedZlib(zs, in, consumed);
    if (produced == out.size()) {
      out.resize(out.size() * 2);
    }
    std::size_t room = std::min(out.size() - produced, kMaxZlibChunk);
    zs.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
    zs.avail_out = static_cast<uInt>(room);
    int flush = (consumed == in.size()) ? Z_FINISH : Z_NO_FLUSH;
    int rc = deflate(&zs, flush);
    produced += room - zs.avail_out;
    if (rc == Z_STREAM_END) {
      break;
    }
    if (rc != Z_OK && rc != Z_BUF_ERROR) {
      throw std::runtime_error(std::string("zlib: deflate failed: ") +
                               zError(rc));
    }
  }
  out.resize(produced);
  return out;
}

}  // namespace

std::string readTextFile(const std::filesystem::path& file,
                         std::size_t maxBytes) {
  return decompressIfGzip(readRaw(file, maxBytes), file.string(), maxBytes);
}

std::string decompressIfGzip(std::string data, const std::string& source,
                             std::size_t maxBytes) {
  if (isGzipMagic(data, 0)) {
    return gunzip(data, source, maxBytes);
  }
  return data;
}

bool hasGzipExtension(const std::filesystem::path& file) {
  return file.extension() == ".gz";
}

void writeTextFile(const std::filesystem::path& file, std::string_view text,
                   bool compress, int gzipLevel) {
  std::string name = file.string();
  std::string packed;
  std::string_view bytes = text;
  if (compress) {
    packed = gzip(text, gzipLevel);
    bytes = packed;
  }
  // Unique per process so that concurrent writers never share a temp file.
  std::filesystem::path tmp =
      file.string() + ".tmp" + std::to_string(::getpid());
  auto fail = [&](const std::string& what) {
    int err = errno;
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw InputError(location(name), what + ": " + std::strerror(err));
  };
  {
    FilePtr f(std::fopen(tmp.string().c_str(), "wb"));
    if (!f) {
      fail("cannot open for writing");
    }
    if (std::fwrite(bytes.data(), 1, bytes.size(), f.get()) != bytes.size()) {
      fail("write error");
    }
    if (std::fclose(f.release()) != 0) {
      fail("write error");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(location(name),
                     "cannot rename temporary file: " + ec.message());
  }
}

void removeIfExists(const std::filesystem::path& file) {
  std::error_code ec;
  std::filesystem::remove(file, ec);
  if (ec) {
    throw InputError(location(file.string()),
                     "cannot remove stale file: " + ec.message());
  }
}

}  // namespace conftrack
