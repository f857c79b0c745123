// HostInputError: what a host throws when the viewer refuses the input it was given: a scene that
// does not open, a point on no face, a pixel with no surface under it, a light move refused. Its
// type and `input` tell it from a GL backend that cannot start (a plain std::runtime_error), so
// that a command can name the option at fault or try again without it, never reading the message.
#pragma once

#include <stdexcept>
#include <string>

namespace penumbra::viewer {

struct HostInputError : std::runtime_error {
    enum class Input { Scene, Point, Pixel, MoveLight };
    // `message`: the viewer's status line, which says why.
    HostInputError(Input input_, const std::string& message)
        : std::runtime_error(message), input(input_) {}
    Input input;
};

}  // namespace penumbra::viewer
