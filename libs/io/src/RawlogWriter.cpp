#include "smap/io/RawlogWriter.h"

#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <stdexcept>

#include "smap/core/AtomicFile.h"

namespace smap::io
{
struct RawlogWriter::Impl
{
    mrpt::io::CFileGZOutputStream stream;
};

RawlogWriter::RawlogWriter(std::string path, int gzipLevel)
    : impl_(std::make_unique<Impl>()),
      path_(std::move(path)),
      tmpPath_(core::temporarySiblingPath(path_))
{
    if (gzipLevel < 0 || gzipLevel > 9)
        throw std::invalid_argument(
            mrpt::format("rawlog '%s': gzip level %d must be in [0, 9]", path_.c_str(), gzipLevel));
    if (!impl_->stream.open(tmpPath_, gzipLevel))
        throw std::runtime_error(mrpt::format("cannot create rawlog '%s'", tmpPath_.c_str()));
}

RawlogWriter::~RawlogWriter()
{
    if (committed_)
        return;
    impl_->stream.close();
    std::error_code ec;
    std::filesystem::remove(tmpPath_, ec);
}

void RawlogWriter::write(const mrpt::serialization::CSerializable& entry)
{
    if (committed_)
        throw std::logic_error("RawlogWriter::write after commit");
    auto arch = mrpt::serialization::archiveFrom(impl_->stream);
    arch << entry;
    entries_++;
}

void RawlogWriter::commit()
{
    if (committed_)
        return;
    impl_->stream.close();
    std::filesystem::rename(tmpPath_, path_);
    committed_ = true;
}
}  // namespace smap::io
