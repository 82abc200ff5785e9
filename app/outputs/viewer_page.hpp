#pragma once
// The page served at "/": the MJPEG stream in an <img> and /status polled once a second
// into a table. Self-contained (no external scripts, styles or fonts): an appliance on an
// isolated network must still show its picture.
#include <string_view>

namespace probeless {

std::string_view viewer_html();

}  // namespace probeless
