// libRoboPlanMrmlBundle.so: the zip side of .mrb bundles through libarchive (rpMrmlBundle.h), loaded
// by the forwarders in RoboPlanMRMLStorage (rpMrmlBundleLoader.cxx) on the first bundle read or
// written: libarchive brings libxml2, ICU, nettle and five compressors, about 8 libraries.
#include <algorithm>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <type_traits>

#include <archive.h>
#include <archive_entry.h>

#include "rpMemoryBudget.h"
#include "rpMrmlBundleEntries.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

struct ReadArchive {
  archive* A = archive_read_new();
  ~ReadArchive() { archive_read_free(this->A); }
};

// libarchive's message, which it does not always set (a null pointer then: found by rpMrmlBundleFuzzer).
std::string ArchiveError(archive* a) {
  const char* text = archive_error_string(a);
  return text ? text : "libarchive gives no reason";
}

// The entry's path ("" when the zip gives none: refused as an empty name).
std::string EntryName(archive_entry* entry) {
  const char* name = archive_entry_pathname(entry);
  return name ? name : "";
}

// Why a zip entry name may not be unpacked ("" when it may): it would land outside the folder.
std::string UnsafeEntryName(const std::string& name) {
  if (name.empty()) return "an empty name";
  if (name[0] == '/' || name[0] == '\\' || (name.size() > 1 && name[1] == ':')) return "an absolute path";
  std::string part;
  for (size_t n = 0; n <= name.size(); ++n) {
    if (n == name.size() || name[n] == '/' || name[n] == '\\') {
      if (part == "..") return "a '..' component that leaves the folder";
      part.clear();
    } else {
      part += name[n];
    }
  }
  return "";
}

bool OpenArchive(ReadArchive& reader, const std::string& zipPath, std::string& error) {
  archive_read_support_format_zip_seekable(reader.A);  // sizes from the central directory
  if (archive_read_open_filename(reader.A, zipPath.c_str(), 1 << 16) != ARCHIVE_OK) {
    error = "'" + zipPath + "' cannot be opened as a zip bundle: " + ArchiveError(reader.A);
    return false;
  }
  return true;
}

// First pass: every entry's name, type and declared size, before any file is written.
bool CheckEntries(const std::string& zipPath, uint64_t maxBytes, std::string& error) {
  ReadArchive reader;
  if (!OpenArchive(reader, zipPath, error)) return false;
  archive_entry* entry = nullptr;
  uint64_t declared = 0;
  int count = 0, status = 0;
  while ((status = archive_read_next_header(reader.A, &entry)) == ARCHIVE_OK) {
    ++count;
    const std::string name = EntryName(entry);
    const std::string why = UnsafeEntryName(name);
    if (!why.empty()) {
      error = "'" + zipPath + "': entry '" + name + "' has " + why + "; the bundle is refused";
      return false;
    }
    const auto type = archive_entry_filetype(entry);
    if (archive_entry_hardlink(entry) || (type != AE_IFREG && type != AE_IFDIR)) {
      error = "'" + zipPath + "': entry '" + name + "' is a link or a special file; the bundle is refused";
      return false;
    }
    if (archive_entry_size_is_set(entry) && archive_entry_size(entry) > 0) declared += archive_entry_size(entry);
    if (declared > maxBytes) {
      error = "'" + zipPath + "' would unpack to more than " + FormatBytes(double(maxBytes)) +
              " (the memory available); the bundle is refused (a zip bomb?)";
      return false;
    }
    archive_read_data_skip(reader.A);
  }
  if (status != ARCHIVE_EOF || count == 0) {
    error = "'" + zipPath + "' is not a readable zip bundle" +
            (status != ARCHIVE_EOF ? ": " + ArchiveError(reader.A) : std::string(": it is empty"));
    return false;
  }
  return true;
}

bool CopyEntryData(archive* a, const fs::path& target, uint64_t& written, uint64_t maxBytes, std::string& error) {
  std::ofstream out(target, std::ios::binary | std::ios::trunc);
  if (!out) {
    error = "cannot write '" + target.string() + "'";
    return false;
  }
  char buffer[1 << 16];
  la_ssize_t size = 0;
  while ((size = archive_read_data(a, buffer, sizeof(buffer))) > 0) {
    written += static_cast<uint64_t>(size);
    if (written > maxBytes) {
      error = "unpacks to more than " + FormatBytes(double(maxBytes)) + " (more than its entries declare: a zip bomb?)";
      return false;
    }
    out.write(buffer, size);
  }
  if (size < 0) {
    error = "corrupt entry data: " + ArchiveError(a);
    return false;
  }
  return static_cast<bool>(out);
}

bool Unpack(const std::string& zipPath, const std::string& folder, uint64_t maxBytes, std::vector<std::string>& entries,
            std::string& error) {
  entries.clear();
  if (!CheckEntries(zipPath, maxBytes, error)) return false;
  ReadArchive reader;
  if (!OpenArchive(reader, zipPath, error)) return false;
  archive_entry* entry = nullptr;
  uint64_t written = 0;
  while (archive_read_next_header(reader.A, &entry) == ARCHIVE_OK) {
    std::string name = EntryName(entry);
    if (!UnsafeEntryName(name).empty()) {  // the first pass refused such names: the zip changed under us
      error = "'" + zipPath + "' changed while it was unpacked; the bundle is refused";
      return false;
    }
    std::replace(name.begin(), name.end(), '\\', '/');
    const fs::path target = fs::path(folder) / name;
    std::error_code ec;
    if (archive_entry_filetype(entry) == AE_IFDIR) {
      fs::create_directories(target, ec);
      continue;
    }
    fs::create_directories(target.parent_path(), ec);
    std::string why;
    if (!CopyEntryData(reader.A, target, written, maxBytes, why)) {
      error = "'" + zipPath + "', entry '" + name + "': " + why;
      return false;
    }
    entries.push_back(name);
  }
  return true;
}

bool Pack(const std::string& folder, const std::string& rootName, const std::string& zipPath, std::string& error) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(folder, ec); !ec && it != fs::recursive_directory_iterator(); ++it)
    if (it->is_regular_file()) files.push_back(fs::relative(it->path(), folder));
  std::sort(files.begin(), files.end());
  archive* a = archive_write_new();
  archive_write_set_format_zip(a);
  bool ok = archive_write_open_filename(a, zipPath.c_str()) == ARCHIVE_OK;
  for (size_t n = 0; ok && n < files.size(); ++n) {
    const fs::path source = fs::path(folder) / files[n];
    std::ifstream in(source, std::ios::binary);
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    archive_entry* entry = archive_entry_new();
    archive_entry_set_pathname(entry, (rootName + "/" + files[n].generic_string()).c_str());
    archive_entry_set_filetype(entry, AE_IFREG);
    archive_entry_set_perm(entry, 0644);
    archive_entry_set_size(entry, static_cast<la_int64_t>(data.size()));
    archive_entry_set_mtime(entry, time(nullptr), 0);
    ok = in.good() || in.eof();
    ok = ok && archive_write_header(a, entry) == ARCHIVE_OK &&
         archive_write_data(a, data.data(), data.size()) == static_cast<la_ssize_t>(data.size());
    archive_entry_free(entry);
  }
  if (!ok) error = "cannot write the bundle '" + zipPath + "': " + ArchiveError(a);
  if (archive_write_close(a) != ARCHIVE_OK && ok) {
    error = "cannot write the bundle '" + zipPath + "': " + ArchiveError(a);
    ok = false;
  }
  archive_write_free(a);
  return ok;
}

}  // namespace
}  // namespace rp

RP_BUNDLE_ENTRY bool roboplan_unpack_bundle(const std::string& zipPath, const std::string& folder, uint64_t maxBytes,
                                            std::vector<std::string>& entries, std::string& error) {
  return rp::Unpack(zipPath, folder, maxBytes, entries, error);
}

RP_BUNDLE_ENTRY bool roboplan_pack_bundle(const std::string& folder, const std::string& rootName,
                                          const std::string& zipPath, std::string& error) {
  return rp::Pack(folder, rootName, zipPath, error);
}

// The entries' types are the C++ functions' (a compile error here when one side changes).
static_assert(std::is_same_v<decltype(&roboplan_unpack_bundle), rp::bundle::UnpackFunction>);
static_assert(std::is_same_v<decltype(&roboplan_pack_bundle), rp::bundle::PackFunction>);
