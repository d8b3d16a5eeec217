"""Lots from other sources become scenario files: OpenStreetMap (:mod:`.osm`) and Lanelet2
maps in Autoware's valet-parking convention (:mod:`.lanelet2`).

Each importer reads its source, projects it into local metres (:mod:`.frame`), builds a
:class:`~lotsim.io.imports.draft.LotDraft` per lot and writes it as a scenario YAML that a
person can read and edit (:meth:`LotDraft.to_yaml`); :mod:`.report` says what became of each
lot. ``docs/import.md`` says what is read, what is inferred and what is dropped.
"""
