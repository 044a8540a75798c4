"""The paper tracks the house holds, in the order the results page shows them: adding a track is its
package (with a ``track.py`` manifest, ``navlab.core.track``) and one entry here."""

from navlab.core.track import Track
from navlab.hj.track import TRACK as HJ
from navlab.pacer.track import TRACK as PACER
from navlab.stack.track import TRACK as STACK
from navlab.surenav.track import TRACK as SURENAV

TRACKS: tuple[Track, ...] = (SURENAV, HJ, PACER, STACK)
