// Writes an MRPT rawlog in the "observations only" layout (one serialized CObservation after
// another, what rawlog-edit, RawLogViewer and CRawlog read), atomically: entries go to a
// temporary sibling that becomes the rawlog on commit(); dropped without commit, nothing is
// left behind.
#pragma once

#include <memory>
#include <string>

namespace mrpt::serialization
{
class CSerializable;
}

namespace smap::io
{
class RawlogWriter
{
public:
    /// `gzipLevel` 0 writes a plain rawlog (fastest), 1-9 gzip-compresses it. Throws
    /// std::runtime_error naming the file when it cannot be created.
    explicit RawlogWriter(std::string path, int gzipLevel = 0);
    ~RawlogWriter();
    RawlogWriter(const RawlogWriter&) = delete;
    RawlogWriter& operator=(const RawlogWriter&) = delete;

    void write(const mrpt::serialization::CSerializable& entry);
    size_t entries() const { return entries_; }
    const std::string& path() const { return path_; }

    /// Closes the stream and renames it to the rawlog's name.
    void commit();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::string path_;
    std::string tmpPath_;
    size_t entries_ = 0;
    bool committed_ = false;
};
}  // namespace smap::io
