#pragma once
// Errors as values at stage boundaries: thrown only from input validation at the start of a stage or from IO.
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
#define MESOHEX_CHECK(cond, msg)                                                                        \
    do {                                                                                                \
        if (!(cond))                                                                                    \
            throw ::mesohex::Error(::mesohex::ErrorCode::NumericalFailure,                              \
                                   std::string("internal check failed: ") + (msg) + " [" #cond "] at " \
                                       + __FILE__ + ":" + std::to_string(__LINE__));                    \
    } while (0)
