#pragma once

/// @file TextFile.hpp
/// Whole-file reading and writing of text, transparently gzip-compressed.
///
/// Event files are read in one go (a TrackML hits file is a few MB) so that
/// parsing runs over one contiguous buffer instead of a stream.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace conftrack {

/// Upper limit on the size of a text file read by readTextFile, before and
/// after decompression (1 GiB; a TrackML hits file is a few MB). Reading
/// stops there with an InputError, so that a link to /dev/zero or a gzip
/// bomb cannot exhaust the memory.
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{1} << 30;

/// Reads a whole file into memory. A file starting with the gzip magic bytes
/// (1f 8b) is decompressed, whatever its name; several concatenated gzip
/// members are supported (as `zcat` does).
///
/// Throws InputError "file: problem" if the file cannot be opened or read,
/// if it or its decompressed data exceed `maxBytes`, if the gzip data is
/// corrupt, truncated ("unexpected end of file") or followed by trailing
/// garbage.
std::string readTextFile(const std::filesystem::path& file,
                         std::size_t maxBytes = kMaxTextFileBytes);

/// The decoding step of readTextFile on bytes already in memory: `data`
/// decompressed if it starts with the gzip magic bytes, else unchanged.
/// `source` names the data in error messages.
std::string decompressIfGzip(std::string data, const std::string& source,
                             std::size_t maxBytes = kMaxTextFileBytes);

/// Default zlib level of the writers. Level 1 writes a TrackML hits file
/// about 5x faster than gzip's default 6 (27 ms instead of 144 ms for
/// 94k hits) for files about 17% larger: writing must not dominate a
/// simulation job. Use 9 for archiving.
inline constexpr int kDefaultGzipLevel = 1;

/// Writes `text` to `file`, gzip-compressed with `gzipLevel` (1 fastest to 9
/// smallest) if `gzip` is true. The data go to a temporary file in the same
/// folder that is renamed at the end, so readers never see a half-written
/// file. Throws InputError if the file cannot be written.
void writeTextFile(const std::filesystem::path& file, std::string_view text,
                   bool gzip, int gzipLevel = kDefaultGzipLevel);

/// True if `file` ends in ".gz" (the writers' rule to choose compression).
bool hasGzipExtension(const std::filesystem::path& file);

/// Removes `file` if it exists (a stale variant of a file being written,
/// e.g. the .csv when the .csv.gz is written). Throws InputError if it
/// exists and cannot be removed.
void removeIfExists(const std::filesystem::path& file);

}  // namespace conftrack
