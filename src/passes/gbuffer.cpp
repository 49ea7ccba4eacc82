#include "passes/gbuffer.h"

#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "gl/buffer.h"
#include "gl/context.h"
#include "gl/mesh.h"
#include "gl/program.h"
#include "gl/texture.h"

namespace blurlab {

GBufferPass::GBufferPass(std::shared_ptr<Context> context) : context_(std::move(context)) {
  context_->make_current();
  variant(GBufferHatching::Scheme::none);
  glCreateFramebuffers(1, &framebuffer_);
  glCreateVertexArrays(1, &empty_vao_);
  check_gl("creating the G-buffer pass");
}

GBufferPass::~GBufferPass() {
  bones_.reset();
  context_->release(nullptr, [framebuffer = framebuffer_, depth = depth_buffer_, base = base_depth_,
                              vao = empty_vao_] {
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteRenderbuffers(1, &depth);
    glDeleteRenderbuffers(1, &base);
    glDeleteVertexArrays(1, &vao);
  });
}

const GBufferPass::Variant& GBufferPass::variant(GBufferHatching::Scheme scheme, bool layers) {
  // Python can make the enum from any int.
  if (scheme < GBufferHatching::Scheme::none || scheme > GBufferHatching::Scheme::threshold)
    throw std::invalid_argument(
        "blurlab: a draw's hatching scheme is not a GBufferHatching.Scheme");
  Variant& made = variants_[layers ? 1 : 0][static_cast<int>(scheme)];
  if (made.program) return made;
  made.program = Program::graphics(
      context_, "passes/gbuffer.vert", "passes/gbuffer.frag",
      {{"HATCHING", std::to_string(static_cast<int>(scheme))}, {"LAYERS", layers ? "1" : "0"}});
  const GLuint id = made.program->id();
  made.locations.view_projection = glGetUniformLocation(id, "view_projection");
  made.locations.sky_from_clip = glGetUniformLocation(id, "sky_from_clip");
  made.locations.sky_projection = glGetUniformLocation(id, "sky_projection");
  made.locations.eye = glGetUniformLocation(id, "eye");
  made.locations.near = glGetUniformLocation(id, "near");
  made.locations.size = glGetUniformLocation(id, "size");
  made.locations.light_direction = glGetUniformLocation(id, "light_direction");
  made.locations.light_color = glGetUniformLocation(id, "light_color");
  made.locations.ambient = glGetUniformLocation(id, "ambient");
  made.locations.background_color = glGetUniformLocation(id, "background_color");
  made.locations.background = glGetUniformLocation(id, "background");
  made.locations.model = glGetUniformLocation(id, "model");
  made.locations.bone_count = glGetUniformLocation(id, "bone_count");
  made.locations.material_color = glGetUniformLocation(id, "material_color");
  made.locations.material_emission = glGetUniformLocation(id, "material_emission");
  made.locations.material_specular = glGetUniformLocation(id, "material_specular");
  made.locations.material_shininess = glGetUniformLocation(id, "material_shininess");
  made.locations.has_texture = glGetUniformLocation(id, "has_texture");
  made.locations.object_id = glGetUniformLocation(id, "object_id");
  made.locations.hatching_scale = glGetUniformLocation(id, "hatching_scale");
  made.locations.alpha_mode = glGetUniformLocation(id, "alpha_mode");
  made.locations.alpha_cutoff = glGetUniformLocation(id, "alpha_cutoff");
  made.locations.layer_capacity = glGetUniformLocation(id, "layer_capacity");
  return made;
}

void GBufferPass::resize_depth(int width, int height) {
  if (width == depth_width_ && height == depth_height_) return;
  glDeleteRenderbuffers(1, &depth_buffer_);
  glCreateRenderbuffers(1, &depth_buffer_);
  glNamedRenderbufferStorage(depth_buffer_, GL_DEPTH_COMPONENT32F, width, height);
  glNamedFramebufferRenderbuffer(framebuffer_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_buffer_);
  depth_width_ = width;
  depth_height_ = height;
}

int GBufferPass::keep_base() {
  if (depth_width_ == 0) throw std::logic_error("blurlab: keep_base needs a G-buffer render first");
  context_->make_current();
  if (base_width_ != depth_width_ || base_height_ != depth_height_) {
    glDeleteRenderbuffers(1, &base_depth_);
    glCreateRenderbuffers(1, &base_depth_);
    glNamedRenderbufferStorage(base_depth_, GL_DEPTH_COMPONENT32F, depth_width_, depth_height_);
    base_width_ = depth_width_;
    base_height_ = depth_height_;
  }
  glCopyImageSubData(depth_buffer_, GL_RENDERBUFFER, 0, 0, 0, 0, base_depth_, GL_RENDERBUFFER, 0, 0,
                     0, 0, depth_width_, depth_height_, 1);
  check_gl("keeping the G-buffer's base");
  base_token_ = ++last_token_;
  return base_token_;
}

void GBufferPass::draw_background(const Variant& variant) {
  // One triangle over the whole image at the far plane, drawn last: it passes the depth test
  // (LEQUAL against the cleared 1.0) only where no geometry was drawn, so the pixels under
  // geometry are neither shaded twice nor written twice. Geometry at depth 1.0 fails GL_LESS
  // against the clear, so the same pixels are background as when it was drawn first.
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_FALSE);
  glUseProgram(variant.program->id());
  glProgramUniform1i(variant.program->id(), variant.locations.background, 1);
  glBindVertexArray(empty_vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDepthMask(GL_TRUE);
}

void GBufferPass::set_frame_uniforms(const Variant& variant, const GBufferCamera& camera,
                                     const GBufferLight& light, int width, int height) {
  const GLuint id = variant.program->id();
  const Locations& at = variant.locations;
  glProgramUniformMatrix4fv(id, at.view_projection, 3, GL_TRUE, &camera.view_projection[0][0]);
  glProgramUniformMatrix4fv(id, at.sky_from_clip, 1, GL_TRUE, camera.sky_from_clip);
  glProgramUniformMatrix4fv(id, at.sky_projection, 2, GL_TRUE, &camera.sky_projection[0][0]);
  glProgramUniform3fv(id, at.eye, 1, camera.eye);
  glProgramUniform1f(id, at.near, camera.near);
  glProgramUniform2f(id, at.size, float(width), float(height));
  glProgramUniform3fv(id, at.light_direction, 1, light.direction);
  glProgramUniform3fv(id, at.light_color, 1, light.color);
  glProgramUniform3fv(id, at.ambient, 1, light.ambient);
  glProgramUniform4fv(id, at.background_color, 1, light.background);
  glProgramUniform1i(id, at.background, 0);
}

void GBufferPass::render(const GBufferTargets& targets, const GBufferCamera& camera,
                         const GBufferLight& light, const std::vector<GBufferDraw>& draws,
                         int over_base) {
  // Colour is always written; depth, motion and object id may be left out (a reference's
  // sub-frames need the colour alone), and their outputs are then not written at all.
  const Texture* outputs[4] = {targets.color.get(), targets.depth.get(), targets.motion.get(),
                               targets.object_id.get()};
  if (!outputs[0]) throw std::invalid_argument("blurlab: the G-buffer pass needs a colour target");
  const int width = targets.color->width(), height = targets.color->height();
  for (const Texture* t : outputs)
    if (t && (t->width() != width || t->height() != height))
      throw std::invalid_argument("blurlab: G-buffer targets differ in size");

  const Texture* sides = targets.motion_sides.get();
  if (sides && (sides->width() != width || sides->height() != height))
    throw std::invalid_argument("blurlab: G-buffer targets differ in size");
  const Texture* lists[4] = {targets.fragment_counts.get(), targets.fragment_surface.get(),
                             targets.fragment_motion.get(), targets.opaque_depth.get()};
  const bool layers = lists[0] != nullptr;
  int capacity = 0;
  if (layers) {
    // The G-buffer targets stay attached but unwritten (colour writes are masked): the opaque
    // depth the fragments are tested against is `opaque_depth`.
    for (const Texture* t : lists)
      if (!t) throw std::invalid_argument("blurlab: fragment lists need all four of their targets");
    // Fragments lie in blocks of W x H, `rows` down and `columns` across
    // (blurlab.translucency.fragment_layout), so capacity x H may exceed the largest texture.
    const int rows = lists[1]->height() / height, columns = lists[1]->width() / width;
    capacity = rows * columns;
    if (lists[0]->width() != width || lists[0]->height() != height || lists[3]->width() != width ||
        lists[3]->height() != height || capacity < 1 || lists[1]->width() != columns * width ||
        lists[1]->height() != rows * height || lists[2]->width() != lists[1]->width() ||
        lists[2]->height() != lists[1]->height())
      throw std::invalid_argument(
          "blurlab: fragment lists must be W x H (counts, opaque depth) and blocks of W x H "
          "(fragments)");
    if (lists[0]->format().internal != GL_R32UI || lists[1]->format().internal != GL_RGBA32F ||
        lists[2]->format().internal != GL_RGBA32F || lists[3]->format().internal != GL_R32F)
      throw std::invalid_argument(
          "blurlab: fragment lists need (H, W) uint32 counts, (kH, W, 4) float32 fragments and "
          "(H, W) float32 opaque depth");
  }

  const bool constant_background = !layers && !outputs[2] && !sides;
  if (over_base != 0) {
    if (!constant_background)
      throw std::invalid_argument(
          "blurlab: a render over a kept base writes no motion and no fragment lists");
    if (over_base != base_token_)
      throw std::invalid_argument(
          "blurlab: that base is not the G-buffer pass's kept one (another keep_base replaced "
          "it)");
    if (base_width_ != width || base_height_ != height)
      throw std::invalid_argument("blurlab: the kept base differs in size from the targets");
  }

  context_->make_current();
  resize_depth(width, height);
  // A target left out (and one left attached from an earlier call) is detached and its draw
  // buffer is GL_NONE; the two-sided motion is written only where asked for.
  GLenum attachments[5];
  for (int i = 0; i < 4; ++i) {
    glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0 + i,
                              outputs[i] ? outputs[i]->id() : 0, 0);
    attachments[i] = outputs[i] ? GLenum(GL_COLOR_ATTACHMENT0 + i) : GLenum(GL_NONE);
  }
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT4, sides ? sides->id() : 0, 0);
  attachments[4] = GL_COLOR_ATTACHMENT4;
  glNamedFramebufferDrawBuffers(framebuffer_, sides ? 5 : 4, attachments);
  if (glCheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw GLError("blurlab: the G-buffer framebuffer is incomplete");

  // Every piece of state the pass relies on is set here: users' moderngl passes share the
  // context and may have changed any of it.
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, width, height);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);  // open meshes (the teapot) show both sides
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  if (over_base != 0) {  // the base's depth; its colour is in the targets already
    glCopyImageSubData(base_depth_, GL_RENDERBUFFER, 0, 0, 0, 0, depth_buffer_, GL_RENDERBUFFER, 0,
                       0, 0, 0, width, height, 1);
  } else {
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
  }
  // Without a motion target (a reference's sub-frames: the colour alone, or colour and depth for
  // translucent scenes), every background output is a constant: it is cleared before the draws
  // instead of shaded after them. The clears write the same floats the background triangle
  // writes, over the same pixels (those no draw passes the depth test at), but cost no fragment
  // work: the raster path is slow on compute chips (docs/gpu.md), and shading the uncovered
  // pixels was most of a sub-frame there.
  if (constant_background && over_base == 0) {
    const float far_depth[4] = {std::numeric_limits<float>::infinity(), 0.0f, 0.0f, 0.0f};
    const float no_object[4] = {-1.0f, 0.0f, 0.0f, 0.0f};
    glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, light.background);
    if (outputs[1]) glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 1, far_depth);
    if (outputs[3]) glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 3, no_object);
  }
  if (layers) {
    // Fragment lists: every fragment of every draw reaches the shader, whatever the order of
    // the draws; the shader tests it against the opaque depth itself.
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_FALSE);
    // The opaque depth was rendered into a target that is still attached and is sampled now:
    // GL defines that read only after a texture barrier (writes stay masked in this pass).
    glTextureBarrier();
    glBindImageTexture(0, lists[0]->id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(1, lists[1]->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(2, lists[2]->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindTextureUnit(3, lists[3]->id());
  }

  // Each variant a draw uses gets this frame's uniforms once, when the first draw needs it.
  bool framed[3] = {false, false, false};
  auto use = [&](GBufferHatching::Scheme scheme) -> const Variant& {
    const Variant& chosen = variant(scheme, layers);
    const int index = static_cast<int>(scheme);
    if (!framed[index]) {
      set_frame_uniforms(chosen, camera, light, width, height);
      if (layers)
        glProgramUniform1i(chosen.program->id(), chosen.locations.layer_capacity, capacity);
    }
    framed[index] = true;
    glUseProgram(chosen.program->id());
    return chosen;
  };

  if (layers) {
    glDisable(GL_DEPTH_TEST);
  } else {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
  }
  for (const GBufferDraw& draw : draws) {
    if (!draw.mesh) throw std::invalid_argument("blurlab: a draw has no mesh");
    const size_t bone_floats = size_t(draw.bone_count) * 3 * 16;
    if (draw.bones.size() != bone_floats)
      throw std::invalid_argument("blurlab: a draw has " + std::to_string(draw.bones.size()) +
                                  " bone floats, expected 3 x " + std::to_string(draw.bone_count) +
                                  " x 16");
    if (draw.mesh->skinned() != (draw.bone_count > 0))
      throw std::invalid_argument("blurlab: skinned meshes need bones, others none");
    const GBufferHatching& hatching = draw.material.hatching;
    const Variant& drawn = use(hatching.scheme);
    const GLuint id = drawn.program->id();
    const Locations& at = drawn.locations;
    if (draw.bone_count > 0) {
      const size_t bytes = bone_floats * sizeof(float);
      if (bytes > bones_capacity_) {
        bones_ = std::make_unique<Buffer>(context_.get(), bytes, Buffer::Usage::storage);
        bones_capacity_ = bytes;
      }
      // Orphaning is not needed: each draw's matrices are written before the draw is issued
      // and GL orders the update after the previous draw's reads.
      glNamedBufferSubData(bones_->id(), 0, static_cast<GLsizeiptr>(bytes), draw.bones.data());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, bones_->id());
    }
    glProgramUniformMatrix4fv(id, at.model, 3, GL_TRUE, &draw.model[0][0]);
    glProgramUniform1i(id, at.bone_count, draw.bone_count);
    glProgramUniform4fv(id, at.material_color, 1, draw.material.color);
    glProgramUniform3fv(id, at.material_emission, 1, draw.material.emission);
    glProgramUniform1f(id, at.material_specular, draw.material.specular);
    glProgramUniform1f(id, at.material_shininess, draw.material.shininess);
    glProgramUniform1i(id, at.has_texture, draw.material.texture ? 1 : 0);
    glProgramUniform1i(id, at.object_id, draw.object_id);
    glProgramUniform1i(id, at.alpha_mode, static_cast<int>(draw.material.alpha_mode));
    glProgramUniform1f(id, at.alpha_cutoff, draw.material.alpha_cutoff);
    if (draw.material.texture) glBindTextureUnit(0, draw.material.texture->id());
    if (hatching.scheme != GBufferHatching::Scheme::none) {
      const bool six_way = hatching.scheme == GBufferHatching::Scheme::six_way;
      if (!hatching.tam_low || (six_way && !hatching.tam_high))
        throw std::invalid_argument("blurlab: a hatched draw lacks its tonal art map textures");
      glBindTextureUnit(1, hatching.tam_low->id());
      if (six_way) glBindTextureUnit(2, hatching.tam_high->id());
    }
    glProgramUniform1f(id, at.hatching_scale, hatching.scale);
    draw.mesh->draw();
  }
  if (!layers && !constant_background) draw_background(use(GBufferHatching::Scheme::none));
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  check_gl("rendering the G-buffer");
  context_->after_pass(layers ? "the G-buffer with fragment lists" : "the G-buffer");
}

}  // namespace blurlab
