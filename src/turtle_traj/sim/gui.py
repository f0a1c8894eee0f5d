"""Optional live window showing the simulator canvas (pygame)."""

from __future__ import annotations

import os

from PIL import Image

from turtle_traj.core.turtlesim_contract import CANVAS_SIZE_PX


class GuiUnavailable(RuntimeError):
    """No window can be opened here; the message says why."""


class Window:
    """A 500x500 window titled TurtleSim that shows rendered frames."""

    def __init__(self) -> None:
        os.environ.setdefault('PYGAME_HIDE_SUPPORT_PROMPT', '1')
        try:
            import pygame
        except ImportError:
            raise GuiUnavailable(
                'the live window needs pygame: pip install "turtle_traj[gui]"') from None
        self._pygame = pygame
        if not (os.environ.get('DISPLAY') or os.environ.get('WAYLAND_DISPLAY')
                or os.environ.get('SDL_VIDEODRIVER')):
            raise GuiUnavailable('no display found (DISPLAY is not set); run without --gui, '
                                 'or under a virtual display such as xvfb-run')
        try:
            pygame.display.init()
            self.surface = pygame.display.set_mode((CANVAS_SIZE_PX, CANVAS_SIZE_PX))
        except pygame.error as error:
            raise GuiUnavailable(f'cannot open a window: {error}') from None
        pygame.display.set_caption('TurtleSim')
        self.closed = False

    def show(self, frame: Image.Image) -> None:
        """Draw a frame and handle window events; a click on close sets `closed`."""
        pygame = self._pygame
        for event in pygame.event.get():
            if event.type == pygame.QUIT:
                self.closed = True
        self.surface.blit(pygame.image.frombytes(frame.tobytes(), frame.size, 'RGB'), (0, 0))
        pygame.display.flip()

    def pixel(self, x: int, y: int) -> tuple[int, int, int]:
        """What the window shows at a pixel (for tests)."""
        return tuple(self.surface.get_at((x, y)))[:3]

    def close(self) -> None:
        self._pygame.display.quit()
