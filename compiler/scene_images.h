// compiler/scene_images.h — every image a built scene uses, decoded once.
//
// pbrt-v3 reads an imagemap texture's file when the Texture directive is met and a light's map
// when the light is made, and caches textures by file and options. decode_scene_images does
// that work at compile time for the whole scene: each distinct (file, processing options)
// pair is decoded once with compiler/image_decoder.h, the distinct images in parallel (oneTBB),
// and the results are stored in SceneDesc::images in first-use order (textures, then lights), so
// the output does not depend on the thread count. TextureDesc::image and LightDesc::image name
// them; an infinite light's image also names its sampling distribution, stored right after it.
// A map that was resampled to powers of two also names its texels as decoded (source_image):
// one-level images stored after all the others, in the same first-use order.
//
// Image parameters describe the stored texels: once an imagemap's "gamma" and "scale" are
// applied to its texels, its entity is set to gamma false and scale 1 (both marked given), so
// compiling pbrtc --dump's output (whose image files hold those texels) stores the same entity.
// Lights keep L, I and scale: they are not applied to the map.
//
// Failure: an image that cannot be read is an error at the texture's or light's directive,
// 'cannot read image "x.png": <reason>' (pbrt-v3 would warn and render a constant). Returns
// false if any error was reported. Not thread-safe on one SceneDesc.
#pragma once

#include "compiler/diagnostics.h"
#include "compiler/scene_desc.h"

namespace pbrtc {

struct BuildProgress;  // compiler/scene_builder.h

// progress, when given, hears phase("images", n) with the number of distinct images to decode,
// when there are any.
bool decode_scene_images(SceneDesc* scene, Diagnostics* diag, BuildProgress* progress = nullptr);

}  // namespace pbrtc
