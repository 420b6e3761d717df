// Writing files so that readers see either nothing or the whole file: write to a temporary name in the same
// folder, then rename it into place (rename is atomic within a file system); several files, all or none.
#pragma once

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace vkrt {

// "`path`: cannot write", with the system's reason where the failed call left one (a full disk: "No space
// left on device"). Called right after the write or flush that failed.
inline std::string cannotWrite(const std::string& path) {
    const int error = errno;
    return path + ": cannot write" +
           (error != 0 ? std::string(" (") + std::strerror(error) + ")" : std::string());
}

// Where writing `path` goes: through a symbolic link to the file it names (so the link stays a link), and
// `direct` when that is not a regular file or a new one (a device such as /dev/stdout, or a pipe), which is
// written as it is, since it cannot be replaced by a rename.
struct OutputTarget {
    std::filesystem::path path;
    bool direct = false;
};

inline OutputTarget outputTarget(const std::string& path) {
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(path, error);  // through links
    if (!error && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
        !std::filesystem::is_directory(status)) {
        return {path, true};
    }
    // Each link in turn (the file it names need not exist yet), at most as many as the system follows.
    std::filesystem::path file(path);
    for (int links = 0;
         links < 40 && std::filesystem::is_symlink(std::filesystem::symlink_status(file, error)); ++links) {
        const std::filesystem::path target = std::filesystem::read_symlink(file, error);
        if (error) break;
        file = target.is_absolute() ? target : file.parent_path() / target;
    }
    return {file, false};
}

// Why this process cannot, or should not, replace the existing regular file `path` by renaming a new one over
// it (empty: it can, or there is no such file). The rename needs only the folder's permission, so without
// this a file read-only to the user was replaced (as cp and editors refuse to), and another user's file in a
// folder with the sticky bit (/tmp) failed only at the rename, after the whole render. A path that cannot be
// looked up, though it may be there, is not replaced either: a loop of symbolic links, which outputTarget
// stops following after as many links as the system follows, was replaced by a regular file.
inline std::string whyNotReplaceable(const std::filesystem::path& path) {
    struct stat file {};
    if (stat(path.c_str(), &file) != 0) {
        const int error = errno;
        return error == ENOENT ? std::string()
                               : "cannot be resolved (" + std::string(std::strerror(error)) + ")";
    }
    if (!S_ISREG(file.st_mode)) return {};
    if (access(path.c_str(), W_OK) != 0) return "is read-only";
    std::filesystem::path folder = path.parent_path();
    if (folder.empty()) folder = ".";
    struct stat dir {};
    const uid_t user = geteuid();
    if (user != 0 && stat(folder.c_str(), &dir) == 0 && (dir.st_mode & S_ISVTX) != 0 && file.st_uid != user &&
        dir.st_uid != user) {
        return "belongs to another user, in a folder whose sticky bit keeps it theirs";
    }
    return {};
}

// Whether two paths name the same file, existing or not (through links, those to files not there yet among
// them, and relative folders). A relative path is made absolute first: weakly_canonical left `img.png` as it
// was while `./img.png` became absolute, so --out img.png --stats ./img.png wrote the stats over the image.
inline bool sameFile(const std::string& a, const std::string& b) {
    const auto resolved = [](const std::string& path) {
        std::error_code error;
        std::filesystem::path file = std::filesystem::absolute(outputTarget(path).path, error);
        if (error) file = outputTarget(path).path;
        std::filesystem::path full = std::filesystem::weakly_canonical(file, error);
        return error ? file.lexically_normal() : full;
    };
    return resolved(a) == resolved(b);
}

// The temporary files being written, for a signal handler that ends the process to remove (unlink() is
// async-signal-safe): an empty name where a slot is free; a path longer than a slot is not listed.
inline constexpr int kTemporaryFileSlots = 8;
inline char gTemporaryFilesBeingWritten[kTemporaryFileSlots][4096] = {};

// Files written together: each is written under a temporary name in its folder when it is staged, and all are
// renamed into place by commit() (rename is atomic within a file system), so that a write that fails (a full
// disk) leaves every file as it was, not a new image beside an earlier run's stats. A batch destroyed before
// its commit removes its temporary files. A device or a pipe (OutputTarget::direct), which cannot be replaced
// by a rename, is written as it is staged.
class FileBatch {
  public:
    FileBatch() = default;
    FileBatch(const FileBatch&) = delete;
    FileBatch& operator=(const FileBatch&) = delete;
    ~FileBatch() { discard(); }

    // Calls write(name) with the name to write `asked` under; if write throws, its temporary file is removed.
    template <typename Write>
    void stage(const std::string& asked, Write&& write) {
        const OutputTarget output = outputTarget(asked);
        if (output.direct) {
            write(asked);
            return;
        }
        Staged staged{temporaryNameFor(output.path), output.path.string(), -1};
        staged.slot = publish(staged.temporary);
        try {
            write(staged.temporary);
        } catch (...) {
            remove(staged);
            throw;
        }
        staged_.push_back(std::move(staged));
    }

    // Renames every staged file into place, with the permissions of the file it replaces where that file is
    // this user's (a private file stayed private). Every target is checked before the first rename, so that
    // one that cannot be replaced leaves all as they were.
    void commit() {
        for (const Staged& staged : staged_) {
            const std::string why = whyNotReplaceable(staged.path);
            if (!why.empty()) throw std::runtime_error(staged.path + ": " + why);
            // The mode alone, and only of this user's own file: another owner's private mode on a file now
            // ours would shut them out of it (the owner is not ours to give back).
            struct stat old {};
            if (stat(staged.path.c_str(), &old) == 0 && S_ISREG(old.st_mode) && old.st_uid == geteuid())
                chmod(staged.temporary.c_str(), old.st_mode & 0777);
        }
        for (Staged& staged : staged_) {
            std::error_code error;
            std::filesystem::rename(staged.temporary, staged.path, error);
            if (error) {
                throw std::runtime_error(staged.path +
                                         ": cannot move the finished file into place: " + error.message());
            }
            unpublish(staged.slot);
            staged.temporary.clear();
        }
        staged_.clear();
    }

  private:
    struct Staged {
        std::string temporary;  // empty once renamed
        std::string path;
        int slot;  // in gTemporaryFilesBeingWritten, -1: not listed
    };

    // `path`'s name and a random suffix, the name cut short where both would pass the 255 bytes a file name
    // may have (a valid name of 235 bytes or more had the write fail after the render).
    static std::string temporaryNameFor(const std::filesystem::path& target) {
        std::random_device device;
        std::ostringstream suffix;
        suffix << ".tmp-" << std::hex << std::setfill('0') << std::setw(8) << device() << std::setw(8)
               << device();
        std::string name = target.filename().string();
        constexpr size_t kLongestName = 255;
        if (name.size() > kLongestName - suffix.str().size()) {
            name.resize(kLongestName - suffix.str().size());
            while (!name.empty() && (static_cast<unsigned char>(name.back()) & 0xc0u) == 0x80u)
                name.pop_back();  // not inside a UTF-8 character
            if (!name.empty() && (static_cast<unsigned char>(name.back()) & 0x80u) != 0)
                name.pop_back();  // its lead
        }
        return (target.parent_path() / (name + suffix.str())).string();
    }

    static int publish(const std::string& file) {
        if (file.size() >= sizeof(gTemporaryFilesBeingWritten[0])) return -1;
        for (int slot = 0; slot < kTemporaryFileSlots; ++slot) {
            if (gTemporaryFilesBeingWritten[slot][0] != '\0') continue;
            // The name first, its first byte last: a handler sees either nothing or the whole name.
            std::copy(file.c_str() + 1, file.c_str() + file.size() + 1,
                      gTemporaryFilesBeingWritten[slot] + 1);
            gTemporaryFilesBeingWritten[slot][0] = file[0];
            return slot;
        }
        return -1;
    }

    static void unpublish(int slot) {
        if (slot >= 0) gTemporaryFilesBeingWritten[slot][0] = '\0';
    }

    static void remove(Staged& staged) {
        std::error_code ignored;
        std::filesystem::remove(staged.temporary, ignored);
        unpublish(staged.slot);
        staged.temporary.clear();
    }

    void discard() {
        for (Staged& staged : staged_) {
            if (!staged.temporary.empty()) remove(staged);
        }
        staged_.clear();
    }

    std::vector<Staged> staged_;
};

// One file written on its own: staged and committed at once. If write throws or the rename fails, the
// temporary file is removed and nothing appears at `path`.
template <typename Write>
void writeFileAtomically(const std::string& asked, Write&& write) {
    FileBatch batch;
    batch.stage(asked, std::forward<Write>(write));
    batch.commit();
}

}  // namespace vkrt
