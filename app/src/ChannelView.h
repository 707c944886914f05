#pragma once
// What a channel looks at (README, "Channels"): its eye on the ownship and its display window,
// composed from [view] — a view offset, an asymmetric frustum, a stereo pair's eye.
//
// A stereo eye sits half the eye separation left or right of the head (the [view] offset) along
// the head's right axis, looking the head's way. With a finite convergence distance Zc its window
// is the head's shifted towards the other eye by e/(2·Zc) in tangent (off-axis stereo, as Wan, Qu
// and Kaufman render a voxel flythrough in stereo): both eyes' windows meet on the plane at Zc,
// where a point has no disparity; a point at depth Z lies fx·e·(1/Z − 1/Zc) pixels further left in
// the right eye's image than in the left eye's. An infinite Zc keeps the axes parallel (a
// collimated display: disparity fx·e/Z).

#include <service/ServiceConfig.h>

#include <fieldcast/Conventions.h>
#include <fieldcast/Intrinsics.h>

namespace fieldcast::app {

/// What a channel looks at: where its eye sits on the ownship and its display window.
struct ChannelView {
  ViewOffset offset;   ///< from the ownship's pose
  Intrinsics display;  ///< the display window's frustum (without margins)
};

/// The offset of `view`'s eye from the ownship when its head sits at `head` (the configured
/// offset, or a host's View Control): the head itself for a centre eye.
ViewOffset eyeOffset(const ViewOffset& head, const ViewConfig& view) noexcept;

/// The view `view` configures for a display window of `widthPx` × `heightPx`; without a frustum of
/// its own, `hfovRad` wide around the view axis with square pixels.
ChannelView channelViewOf(const ViewConfig& view, int widthPx, int heightPx, double hfovRad) noexcept;

}  // namespace fieldcast::app
