#include "roadcross/preprocess/common/errors.hpp"

namespace roadcross::preprocess {

InputError::InputError(const std::string& file, const std::string& what)
    : std::runtime_error(file + ": " + what), file_(file) {}

}  // namespace roadcross::preprocess
