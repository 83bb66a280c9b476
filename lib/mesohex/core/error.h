#pragma once
// Errors as values at stage boundaries: thrown only from input validation at the start of a stage or from IO.
#include <new>
#include <stdexcept>

#include <string>

namespace mesohex {

enum class ErrorCode { InvalidInput = 1, UnsupportedConfiguration = 2, IoError = 3, NumericalFailure = 4 };

// What an error refers to: a file line, or a skeleton / mesh element.
struct ElementRef {
    enum class Kind { None, FileLine, SkeletonVertex, SkeletonEdge, SkeletonFace, Hex, Quad } kind = Kind::None;
    int index = -1;  // element id or 1-based line number
};

class Error : public std::runtime_error {
public:
    Error(ErrorCode code, const std::string& message, ElementRef where = {})
        : std::runtime_error(message), code_(code), where_(where) {}
    ErrorCode code() const { return code_; }
    const ElementRef& where() const { return where_; }

private:
    ErrorCode code_;
    ElementRef where_;
};

// A mesohex::Error for an exception that is not one: std::bad_alloc ("out of memory") or a foreign library's
// failure (CGAL::Failure_exception, an Eigen or TBB error), as NumericalFailure with `context` (the file and stage
// that were being processed) in front. Used at the stage boundaries of the CLI so that no run ends on a bare
// foreign message.
inline Error foreign_error(const std::exception& e, const std::string& context) {
    const bool oom = dynamic_cast<const std::bad_alloc*>(&e) != nullptr;
    return Error(ErrorCode::NumericalFailure,
                 context + ": " + (oom ? std::string("out of memory") : "internal failure: " + std::string(e.what())));
}

// Exit status the CLI uses for each code (0 = success, 1 = generic failure, 5 = mesh has inverted hexes).
inline int exit_code(ErrorCode c) {
    switch (c) {
        case ErrorCode::InvalidInput: return 2;
        case ErrorCode::UnsupportedConfiguration: return 3;
        case ErrorCode::IoError: return 4;
        case ErrorCode::NumericalFailure: return 6;
    }
    return 1;
}

}  // namespace mesohex

// Cheap invariant check that stays on in release builds. A failure is a bug, not bad input.
#define MESOHEX_CHECK(cond, msg)                                                                                       \
    do {                                                                                                               \
        if (!(cond))                                                                                                   \
            throw ::mesohex::Error(::mesohex::ErrorCode::NumericalFailure, std::string("internal check failed: ") +    \
                                                                               (msg) + " [" #cond "] at " + __FILE__ + \
                                                                               ":" + std::to_string(__LINE__));        \
    } while (0)
