#pragma once

// VTK reports failures through ErrorEvent (printing them to its output window when nobody
// listens) rather than by return value. VtkErrors listens, so that the messages end up in our
// exceptions instead of on stderr. Objects nobody watches (a reader's zlib decompressor) still
// print through vtkOutputWindow and vtkLogger, as coloured "ERR|" lines beside our own one-line
// message; the first VtkErrors turns both off for the process (the reader's own error, which
// it watches, still says what failed). Include only from .cpp files that use VTK.

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkOutputWindow.h>

#include <cctype>
#include <string>

namespace vessel::detail {

class VtkErrors
{
public:
    VtkErrors()
    {
        static const bool quiet = [] {
            vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
            vtkOutputWindow::GetInstance()->SetDisplayModeToNever();
            return true;
        }();
        (void)quiet;
        errors_->SetClientData(this);
        errors_->SetCallback([](vtkObject*, unsigned long event, void* self, void* message) {
            auto* me = static_cast<VtkErrors*>(self);
            if (event != vtkCommand::ErrorEvent)
                return;  // warnings (e.g. unknown array types) are dropped
            if (me->message_.empty() && message)
                me->message_ = static_cast<const char*>(message);
            me->failed_ = true;
        });
    }
    VtkErrors(const VtkErrors&) = delete;
    VtkErrors& operator=(const VtkErrors&) = delete;

    //! Collect the errors (and drop the warnings) \p object reports.
    void watch(vtkObject* object)
    {
        if (!object)
            return;
        object->AddObserver(vtkCommand::ErrorEvent, errors_);
        object->AddObserver(vtkCommand::WarningEvent, errors_);
    }
    //! The observer, for APIs that take one (vtkXMLReader::SetParserErrorObserver).
    vtkCommand* command() { return errors_; }
    bool failed() const { return failed_; }
    //! The first error; VTK's "ERROR: In <file>, line N\n<class> (<ptr>): " prefix removed.
    std::string message() const
    {
        std::string m = message_;
        while (!m.empty() && std::isspace(static_cast<unsigned char>(m.back())))
            m.pop_back();
        const auto colon = m.find("): ");
        return colon == std::string::npos ? m : m.substr(colon + 3);
    }

private:
    vtkNew<vtkCallbackCommand> errors_;
    std::string message_;
    bool failed_ = false;
};

}  // namespace vessel::detail
