#pragma once

// Writing a file so that a failed run never leaves a partial one and never writes through a
// planted link: the data goes to a new temporary file in the target's folder, created with
// mkstemps() (O_CREAT | O_EXCL: a name that did not exist, so neither an old file nor a symbolic
// link is ever opened), and is renamed onto the target only after fflush(), fsync() and fclose()
// have all succeeded (POSIX rename() replaces the target atomically within one file system; the
// pattern of Linux's "ext4 and data loss" advice, and of glib's g_file_set_contents()).

#include <cstdio>
#include <functional>
#include <string>

namespace vessel::detail {

//! \brief A temporary file for the target \p target, named `TARGET.XXXXXX.tmp` (XXXXXX unique)
//! in the target's folder, so the final rename never crosses file systems.
//! Created empty with mode 0666 minus the umask (as fopen() would); removed by the destructor
//! unless commit() succeeded.
class TempFile
{
public:
    //! \param who names the caller in every IoError message.
    //! \throw IoError if the folder does not exist or is not writable.
    TempFile(const std::string& target, const std::string& who);
    ~TempFile();
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;

    //! The temporary file's name, for writers that open a file by name (VTK, cairo); they
    //! reopen the empty file this object created.
    const std::string& path() const { return tmp_; }

    //! The temporary file as a stream opened for binary writing, owned by this object.
    FILE* stream();

    //! \brief Checks the stream for write errors, then fflush(), fsync() and fclose() (each
    //! result checked), checks that the name still refers to the file created here, and renames
    //! it onto the target.
    //! \param write_error the errno of a failed write to stream(), if the caller has it (a large
    //! fwrite() bypasses the buffer, so fflush() cannot repeat its failure); 0 if none.
    //! \throw IoError naming the target and the system's reason (e.g. "File too large", "No
    //! space left on device"); the temporary file is then removed.
    void commit(int write_error = 0);

private:
    void fail(const std::string& what, int error);  // throws IoError

    std::string target_, tmp_, who_;
    int fd_ = -1;
    FILE* file_ = nullptr;
    bool committed_ = false;
};

//! Writes \p path through a TempFile: \p write gets its stream; then TempFile::commit().
//! \throw IoError (naming \p who) on any failure, leaving \p path as it was.
void write_atomically(const std::string& path, const std::string& who,
                      const std::function<void(FILE*)>& write);

//! As write_atomically(), for writers that open a file by name: \p write gets the temporary
//! file's name and must throw if it could not write it completely.
void write_atomically_by_name(const std::string& path, const std::string& who,
                              const std::function<void(const std::string& tmp)>& write);

//! \brief Makes a write beyond the process's file size limit (`ulimit -f`, RLIMIT_FSIZE) fail
//! with EFBIG instead of killing the process with SIGXFSZ (POSIX write(): "If the request would
//! cause the file size to exceed the soft file size limit for the process and there is no room
//! for any bytes to be written, the request shall fail and the implementation shall generate
//! the SIGXFSZ signal"; ignored, only the error remains). Changes the disposition only if it is
//! the default one, so an application's own handler is kept. Called by TempFile.
void ignore_file_size_signal();

}  // namespace vessel::detail
