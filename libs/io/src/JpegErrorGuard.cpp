// A damaged JPEG inside a rawlog must not end the process. MRPT 2.5 decodes a CImage's JPEG
// bytes (CImage::loadFromStreamAsJPEG) with libjpeg's default error handler, which ends the
// process: one corrupt frame in a recording ended the whole run (found by fuzz_rawlog).
// This file defines jpeg_std_error, the call every libjpeg user makes to get the default
// handler. smap_io is loaded before libjpeg, so the dynamic linker binds MRPT's calls (and
// OpenCV's) to this one. It fills the handler as libjpeg does, then makes error_exit throw
// instead, after freeing the decompressor's memory: the exception unwinds through libjpeg and
// MRPT (built with unwind tables, as Debian's amd64 C code is) to RawlogSource, which reports
// the entry as damaged. Callers that install their own error_exit after this call (OpenCV's
// imgcodecs) keep theirs.
#include <dlfcn.h>

#include <cstdio>  // before jpeglib.h, which uses FILE
#include <stdexcept>
#include <string>
// clang-format off
#include <jpeglib.h>
// clang-format on

namespace
{
using StdError = jpeg_error_mgr* (*)(jpeg_error_mgr*);

using Destroy = void (*)(j_common_ptr);

[[noreturn]] void throwingErrorExit(j_common_ptr cinfo)
{
    char message[JMSG_LENGTH_MAX] = {0};
    (*cinfo->err->format_message)(cinfo, message);
    // The caller will not get to destroy the decompressor once we throw: free its memory
    // here (libjpeg's own jpeg_destroy; the object is not touched again).
    static const auto destroy = reinterpret_cast<Destroy>(dlsym(RTLD_DEFAULT, "jpeg_destroy"));
    if (destroy != nullptr)
        destroy(cinfo);
    throw std::runtime_error(std::string("damaged JPEG image: ") + message);
}

StdError libjpegStdError()
{
    // The next definition after this one: libjpeg's.
    static const auto next = reinterpret_cast<StdError>(dlsym(RTLD_NEXT, "jpeg_std_error"));
    return next;
}
}  // namespace

extern "C" __attribute__((visibility("default"))) jpeg_error_mgr* jpeg_std_error(
    jpeg_error_mgr* err)
{
    const StdError next = libjpegStdError();
    if (next == nullptr)
        throw std::runtime_error("libjpeg's jpeg_std_error is not loaded");
    next(err);
    err->error_exit = throwingErrorExit;
    return err;
}
