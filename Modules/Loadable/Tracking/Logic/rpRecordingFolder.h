#pragma once
// The one folder remote clients may record into (`roboplan track --record-dir`, PLUS's
// OutputDirectory): StartRecording's OutputFilename is a file name inside it, nothing else.
//
// Refused, with a message naming why: an absolute path, a `..` or any other folder part (`/`,
// or a Windows `\`), a name that is a symbolic link, an empty or hidden name, control
// characters, a name longer than the file system allows, and anything but a PLUS sequence
// (.igs.mha, .igs.nrrd). A name that exists already is made unique as PLUS names recordings,
// with the date and time before the extension (`Recording_20261128_213700.igs.mha`, then
// `_2`, `_3` ...): an existing file is never opened, let alone overwritten. The folder is
// opened once (a descriptor) and every file is created relative to it with O_EXCL and
// O_NOFOLLOW, so no later rename, link or race can send a recording elsewhere.
#include <ctime>
#include <string>

namespace rp {

class RecordingFolder {
 public:
  RecordingFolder() = default;
  ~RecordingFolder();
  RecordingFolder(const RecordingFolder&) = delete;
  RecordingFolder& operator=(const RecordingFolder&) = delete;

  /// Opens the folder (it must exist). False with `error`.
  bool Open(const std::string& path, std::string& error);
  bool IsOpen() const { return this->Fd >= 0; }
  /// The folder as given, and as an absolute path (for messages).
  const std::string& Path() const { return this->Folder; }

  struct Created {
    int Fd = -1;             // open for writing, new and empty; the caller owns it
    std::string Name;        // the file name written (the one asked for, or made unique)
    std::string Path;        // folder + name
    bool MadeUnique = false; // the name asked for existed
  };
  /// Creates a new file for the name a client asked for. False with `error` (the reason).
  /// `now` stamps a name made unique (tests give a fixed time).
  bool Create(const std::string& requested, Created& created, std::string& error, std::time_t now = std::time(nullptr)) const;

  /// Why `name` may not be a recording's file name ("" when it may).
  static std::string CheckName(const std::string& name);

 private:
  int Fd = -1;
  std::string Folder;
};

}  // namespace rp
