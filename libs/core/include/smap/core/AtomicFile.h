// Writing an output file so that readers never see it half-written: everything goes to a
// temporary name in the same directory, which is renamed over the target only on success.
#pragma once

#include <fstream>
#include <functional>
#include <string>

namespace smap::core
{
/// Temporary sibling of `path` that keeps its extension (writers such as cv::imwrite choose the
/// format by extension): "dir/.name.tmp-<pid>.ext".
std::string temporarySiblingPath(const std::string& path);

/// Calls `writer(tmpPath)`, then renames tmpPath to `path`. If the writer throws, or leaves no
/// file behind, the temporary is removed, `path` is untouched, and the error propagates.
void writeFileAtomically(const std::string& path,
                         const std::function<void(const std::string&)>& writer);

/// Says whether an existing, non-empty folder may be replaced: typically, whether it is an
/// earlier output of the same tool.
using ReplaceCheck = std::function<bool(const std::string& existingDir)>;

/// The same for a folder: `writer(tmpDir)` fills a fresh temporary sibling folder, which then
/// replaces `dir`. On failure the temporary folder is removed, `dir` is untouched, and the
/// error propagates. Before anything is written, InputError refuses a `dir` that names no
/// folder of its own (".", "..", "/"), one that exists and is not a folder, and an existing
/// non-empty folder that `mayReplace` does not accept (none given: only empty folders are
/// replaced): a user's --out must never delete what the tool did not write.
void writeDirectoryAtomically(const std::string& dir,
                              const std::function<void(const std::string&)>& writer,
                              const ReplaceCheck& mayReplace = {});

/// A text output stream that becomes `path` on commit(); dropped without commit, it leaves
/// nothing behind.
class AtomicTextFile
{
public:
    explicit AtomicTextFile(std::string path);
    ~AtomicTextFile();
    AtomicTextFile(const AtomicTextFile&) = delete;
    AtomicTextFile& operator=(const AtomicTextFile&) = delete;

    std::ostream& stream() { return out_; }
    /// Flushes, checks for write errors (throws std::runtime_error naming the file), renames.
    void commit();

private:
    std::string path_;
    std::string tmpPath_;
    std::ofstream out_;
    bool committed_ = false;
};
}  // namespace smap::core
