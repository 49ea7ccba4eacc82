"""The image size that renders, blurs, references and studies use unless given one."""

DEFAULT_SIZE = (640, 360)  # (width, height) in pixels
