#include "conftrack/simulation/generators/HepMCText.hpp"

#include "conftrack/core/Error.hpp"

#include <zlib.h>

#include <fstream>
#include <memory>

#include "HepMCTextCheck.hpp"

namespace conftrack::hepmc {

using detail::Checker;
using detail::kMaxLineLength;
using detail::Line;
using detail::splitLines;
using detail::startsWith;
using detail::validateAsciiV3;
using detail::validateIoGenEvent;

std::string formatName(Format format) {
  switch (format) {
    case Format::eAsciiV3:
      return "Asciiv3";
    case Format::eIoGenEvent:
      return "IO_GenEvent";
    default:
      return "unknown";
  }
}

std::string gunzip(std::string_view data, const std::string& source,
                   std::size_t maxBytes) {
  std::string out;
  z_stream zs{};
  // 16 + MAX_WBITS: gzip wrapper only.
  if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) {
    throw InputError(source, "zlib initialisation failed");
  }
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  zs.avail_in = static_cast<uInt>(data.size());
  // Not zero-filled, and no larger than the limit allows: a 256 kB
  // zeroed buffer per call cost 1.5 ms (most of the gzip fuzz target's
  // time, under ASan) on inputs of a few bytes.
  constexpr std::size_t kChunk = std::size_t{1} << 18;
  const std::size_t chunk = maxBytes < kChunk ? maxBytes + 1 : kChunk;
  const std::unique_ptr<char[]> buffer =
      std::make_unique_for_overwrite<char[]>(chunk);
  int ret = Z_OK;
  while (true) {
    zs.next_out = reinterpret_cast<Bytef*>(buffer.get());
    zs.avail_out = static_cast<uInt>(chunk);
    ret = inflate(&zs, Z_NO_FLUSH);
    if (ret != Z_OK && ret != Z_STREAM_END && ret != Z_BUF_ERROR) {
      const std::string msg = zs.msg != nullptr ? zs.msg : "error";
      inflateEnd(&zs);
      throw InputError(source, "corrupt gzip data (" + msg + ")");
    }
    out.append(buffer.get(), chunk - zs.avail_out);
    if (out.size() > maxBytes) {
      inflateEnd(&zs);
      throw InputError(source, "decompressed data larger than " +
                                   std::to_string(maxBytes) + " bytes");
    }
    if (ret == Z_STREAM_END) {
      // Another gzip member may follow (as zcat reads them).
      if (zs.avail_in == 0) {
        break;
      }
      if (inflateReset(&zs) != Z_OK) {
        inflateEnd(&zs);
        throw InputError(source, "corrupt gzip data");
      }
      continue;
    }
    if (ret == Z_BUF_ERROR || (zs.avail_in == 0 && zs.avail_out != 0)) {
      // No progress possible: the input ended inside a member.
      inflateEnd(&zs);
      throw InputError(source, "truncated gzip data (unexpected end of file)");
    }
  }
  inflateEnd(&zs);
  return out;
}

std::string loadFile(const std::filesystem::path& path, std::size_t maxBytes) {
  const std::string source = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw MissingFileError(source, "no such file");
  }
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(source, "not a regular file");
  }
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) {
    throw InputError(source, "cannot determine the file size");
  }
  if (size > maxBytes) {
    throw InputError(source,
                     "file larger than " + std::to_string(maxBytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(source, "cannot open the file");
  }
  std::string data(size, '\0');
  in.read(data.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::size_t>(in.gcount()) != size) {
    throw InputError(source, "cannot read the file");
  }
  if (data.empty()) {
    throw InputError(source, "empty file");
  }
  if (data.size() >= 2 && static_cast<unsigned char>(data[0]) == 0x1f &&
      static_cast<unsigned char>(data[1]) == 0x8b) {
    data = gunzip(data, source, maxBytes);
    if (data.empty()) {
      throw InputError(source, "empty file (after decompression)");
    }
  }
  return data;
}

Format detectFormat(std::string_view text) {
  std::size_t pos = 0;
  for (int n = 0; n < 20 && pos < text.size(); ++n) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) {
      end = text.size();
    }
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) {
      line.remove_suffix(1);
    }
    if (line.empty() || startsWith(line, "HepMC::Version")) {
      continue;
    }
    if (line == "HepMC::Asciiv3-START_EVENT_LISTING") {
      return Format::eAsciiV3;
    }
    if (line == "HepMC::IO_GenEvent-START_EVENT_LISTING") {
      return Format::eIoGenEvent;
    }
    return Format::eUnknown;
  }
  return Format::eUnknown;
}

TextSummary validate(std::string_view text, const std::string& source) {
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    throw InputError(source, "empty file");
  }
  if (text.find('\0') != std::string_view::npos) {
    throw InputError(source, "binary data, not a HepMC text file");
  }
  const Format format = detectFormat(text);
  if (format == Format::eUnknown) {
    throw InputError(source,
                     "unknown format (expected a 'HepMC::Asciiv3' or "
                     "'HepMC::IO_GenEvent' START_EVENT_LISTING line)");
  }
  const std::vector<Line> lines = splitLines(text);
  const Checker checker(source);
  for (const Line& line : lines) {
    if (line.text.size() > kMaxLineLength) {
      checker.fail(line.number, "line longer than the HepMC3 reader's " +
                                    std::to_string(kMaxLineLength) +
                                    "-character buffer");
    }
  }
  TextSummary summary = format == Format::eAsciiV3
                            ? validateAsciiV3(lines, checker)
                            : validateIoGenEvent(lines, checker);
  if (summary.numEvents == 0) {
    throw InputError(source, "no events");
  }
  return summary;
}

}  // namespace conftrack::hepmc
